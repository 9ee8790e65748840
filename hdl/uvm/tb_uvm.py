"""cocotb test module of the pyuvm bench (hdl/uvm/pmu50_uvm): one cocotb test per UVM test,
selected by name (``COCOTB_TEST_FILTER`` / the runner's ``testcase``). Knobs: pmu50_uvm/tests.py."""

import pyuvm

from pmu50_uvm import tests

for _cls in (
    tests.RandomTest,
    tests.VectorTest,
    tests.ScenarioTest,
    tests.RegressSeedTest,
    tests.RegisterTest,
):
    pyuvm.test()(_cls)
