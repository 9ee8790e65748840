"""PMU 50 reference model (patent US 2022/0041215 A1) for Python.

The cycle-accurate model of the digital core of power management unit 50, written in Rust, as a
Python package (docs/python.md):

- :class:`Core`: the core, one rising clock edge per :meth:`Core.step`, configured with the
  scenario ``[core]`` names (``Core(x="6.6 ms", cth=4)``); :meth:`Core.peek`, :meth:`Core.regs`,
  :meth:`Core.read`, :attr:`Core.tick`, :meth:`Core.signals`.
- :class:`Scenario`: a scenario file (``Scenario.load(path)``, ``Scenario.from_str(text)``) and
  its run with the environment models (:meth:`Scenario.run`), the summary of ``pmu50 run``.
- :class:`Coverage`: the functional coverage model sampled at every edge
  (``cov.step(core, **inputs)``), written as ``coverage.json`` (:meth:`Coverage.write`);
  :func:`merge_coverage` merges such files as ``pmu50 merge``, :func:`export_ucis` exports one
  to UCIS XML.
- :func:`signal_table`: names and widths of every port, register and internal signal;
  :data:`REGISTER_MAP`: the register map (name, address, width, access);
  :data:`CORE_PARAMETERS`: the ``[core]`` parameter names.

Errors: :class:`ConfigError` and :class:`ScenarioError` (both ``ValueError``) carry the CLI's
messages; :class:`CoverageError` (a ``ValueError``) a coverage file that cannot be read or
merged; :class:`SimulationError` a failed run; :class:`InternalError` a caught Rust panic.
"""

from ._native import (
    CORE_PARAMETERS,
    REGISTER_MAP,
    Check,
    ConfigError,
    Core,
    Coverage,
    CoverageError,
    DarkCurrent,
    InputValues,
    InternalError,
    Internals,
    KeyOff,
    Outputs,
    Pulse,
    PulseRun,
    PulseTable,
    Readout,
    RunResult,
    Scenario,
    ScenarioError,
    Signal,
    SimulationError,
    Trace,
    __version__,
    export_ucis,
    merge_coverage,
    signal_table,
)

__all__ = [
    "CORE_PARAMETERS",
    "REGISTER_MAP",
    "Check",
    "ConfigError",
    "Core",
    "Coverage",
    "CoverageError",
    "DarkCurrent",
    "InputValues",
    "InternalError",
    "Internals",
    "KeyOff",
    "Outputs",
    "Pulse",
    "PulseRun",
    "PulseTable",
    "Readout",
    "RunResult",
    "Scenario",
    "ScenarioError",
    "Signal",
    "SimulationError",
    "Trace",
    "__version__",
    "export_ucis",
    "merge_coverage",
    "signal_table",
]
