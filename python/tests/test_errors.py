"""No Rust panic crosses into Python; the exception classes."""

import pytest

import pmu50
from pmu50 import _native


def test_a_panic_becomes_internal_error():
    with pytest.raises(pmu50.InternalError, match=r"Rust panic `boom 42`; this is a bug"):
        _native._panic_for_test("boom 42")
    # and the interpreter goes on
    assert pmu50.Core().step(ig=1).si == 660


def test_exception_hierarchy():
    assert issubclass(pmu50.ConfigError, ValueError)
    assert issubclass(pmu50.ScenarioError, ValueError)
    assert issubclass(pmu50.SimulationError, RuntimeError)
    assert issubclass(pmu50.InternalError, RuntimeError)
    assert not issubclass(pmu50.InternalError, ValueError)
