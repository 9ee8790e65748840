"""pytest of the formal kit's tests (hdl/formal/tests): pytest puts this folder, which holds the
package pmu50_formal, on the module path (a conftest.py outside a package), so the tests import
the package as the commands run.py and coverage.py do."""
