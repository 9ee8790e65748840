"""Type stubs of the native module pmu50._native (python/src/*.rs); `pmu50` re-exports it all."""

from collections.abc import Iterator, Mapping
from os import PathLike
from pathlib import Path
from typing import Literal, TypedDict, overload

from typing_extensions import Unpack

__version__: str

CORE_PARAMETERS: list[str]
"""The ``[core]`` parameter names: clock, sync_depth, cnt_width, adaptive, pw, pi, ps, x, min,
t1, t2, cth, smp_on."""

REGISTER_MAP: list[tuple[str, int, int, str]]
"""The register map of docs/spec.md: (name, address, width, access "RO" / "RW" / "RO/W1C")."""

class ConfigError(ValueError):
    """An illegal ``[core]`` value; the message is the CLI's without ``file:line:``."""

class ScenarioError(ValueError):
    """An invalid scenario; the message is the CLI's: ``file:line: `field`: ...``."""

class SimulationError(RuntimeError):
    """A scenario run failed (environment model, output file)."""

class InternalError(RuntimeError):
    """A Rust panic caught at the boundary (a bug)."""

class CoverageError(ValueError):
    """A coverage file that cannot be read or merged (corrupt, of another model or format, a run
    counted twice); the message names the file and the reason."""

SignalKind = Literal["input", "output", "register", "internal"]

class Signal:
    """One row of the signal table."""

    kind: SignalKind
    name: str
    """Port or internal name; registers: ``block.register`` (VCD path below ``pmu50``)."""
    width: int
    signed: bool
    """Two's complement (cnt_s, cnt_c)."""
    reset: int | None
    """A register's reset value in this configuration; None for ports and internals."""
    meaning: str
    patent: str
    """Patent paragraphs, e.g. ``[0096]-[0097]``."""

class _Values:
    """Signal values by name: ``v.si``, ``v["si"]``; one-bit signals are 0 or 1."""

    def __getattr__(self, name: str) -> int: ...
    def __getitem__(self, name: str) -> int: ...
    def __contains__(self, name: str) -> bool: ...
    def __len__(self) -> int: ...
    def __eq__(self, other: object) -> bool: ...
    def names(self) -> list[str]: ...
    def values(self) -> list[int]: ...
    def widths(self) -> dict[str, int]: ...
    def to_dict(self) -> dict[str, int]: ...
    def mismatches(self, got: Mapping[str, object]) -> list[tuple[str, int, object]]:
        """``[(signal, expected, got)]`` for every signal whose value in ``got`` differs."""

class Outputs(_Values):
    """The 23 top-level outputs of one tick (docs/signals.md)."""

    sig: int
    vr_hi: int
    vm_en: int
    vs1_en: int
    vs2_en: int
    vp_en: int
    rail_hi: int
    st: int
    sr: int
    ps_win: int
    smp: int
    cs: int
    cc: int
    cnt_s: int
    """CNT_W bits, two's complement (upper bits 0)."""
    cnt_c: int
    cnt_r: int
    si: int
    """Drive interval, ticks."""
    hist_s: int
    hist_c: int
    diag: int
    quadrant_skip: int
    bus_rdata: int
    bus_err: int

class Internals(_Values):
    """Combinational internals of one cycle."""

    kon: int
    koff: int
    upd: int
    first: int
    chg_s: int
    chg_c: int
    skip_clr: int
    fig17: int
    """FIG. 17 branch: 0 idle, 1 S1, 2 S5, 3 S6, 4 S7, 5 S9, 6 S10, 7 fixed cycle."""
    fig18: int
    """FIG. 18 path: 0 idle, 1 S23, 2 S21 repeat, 3 S28, 4 S26 repeat, 5 no change."""

class InputValues(_Values):
    """The 7 top-level inputs as applied."""

    ig: int
    vs2_ok: int
    cmp_s: int
    cmp_c: int
    bus_we: int
    bus_addr: int
    bus_wdata: int

class Trace:
    """One edge: outputs before and after, internals of the cycle, inputs applied."""

    tick: int
    before: Outputs
    internals: Internals
    after: Outputs
    inputs: InputValues

_Bit = bool | int

class _Config(TypedDict, total=False):
    """The keyword arguments of :class:`Core` (the scenario ``[core]`` table); each one left out
    takes the patent's value (the default named in its docstring)."""

    clock: str
    """Clock period. Default ``"10 us"``."""
    sync_depth: int
    """Flip-flops of the key synchronizer (structural), 1 to 4. Default ``2``."""
    cnt_width: int
    """Width of cnt_s and cnt_c (structural), 2 to 16. Default ``16``."""
    adaptive: bool
    """Adaptive interval (``False``: the fixed cycle ``x`` of the first embodiment).
    Default ``True``."""
    pw: str
    """Waiting period Pw of one intermittent output. Default ``"50 us"``."""
    pi: str
    """Idle period Pi of one intermittent output. Default ``"120 us"``."""
    ps: str
    """Sampling period Ps of one intermittent output. Default ``"50 us"``."""
    x: str
    """Maximum interval, the first time interval (register si_max). Default ``"6.6 ms"``."""
    min: str
    """Minimum interval (register si_min). Default ``"2.2 ms"``."""
    t1: str
    """Shortening step T1. Default ``"2.2 ms"``."""
    t2: str
    """Expanding step T2. Default ``"1.1 ms"``."""
    cth: int
    """Count threshold Cth. Default ``4``."""
    smp_on: str
    """Sampling period while the key is on. Default ``"100 us"``."""

class _Inputs(TypedDict, total=False):
    """The inputs of one clock edge, by their port names; each one left out is 0."""

    ig: _Bit
    vs2_ok: _Bit
    cmp_s: _Bit
    cmp_c: _Bit
    bus_we: _Bit
    bus_addr: int
    bus_wdata: int

class Core:
    """The digital core of PMU 50 at power-on reset (rtl_model/core/src/pmu50.rs).

    Keyword arguments are the scenario ``[core]`` table: durations as strings with a unit
    (``"2.2 ms"``, ``"220 us"``), defaults the patent's. An illegal value raises
    :class:`ConfigError` with the CLI's message; an unknown name or a wrong type ``TypeError``.
    """

    def __init__(self, **config: Unpack[_Config]) -> None: ...
    def step(self, **inputs: Unpack[_Inputs]) -> Outputs:
        """One rising clock edge with these inputs; the outputs after it."""
    def step_traced(self, **inputs: Unpack[_Inputs]) -> Trace:
        """Like :meth:`step`, with outputs before and after, internals and inputs."""
    def peek(self) -> Outputs:
        """The outputs of the current tick (no edge)."""
    def regs(self) -> dict[str, dict[str, int]]:
        """Every register: ``{block: {register: value}}``."""
    def read(self, addr: int) -> int:
        """The register file's read mux at ``addr`` this tick."""
    def reset(self) -> None:
        """Back to power-on reset; ``tick`` restarts at 0."""
    @property
    def tick(self) -> int:
        """Edges taken since reset."""
    @property
    def config(self) -> dict[str, str | int | bool]:
        """The configuration as keyword arguments of ``Core()``."""
    @property
    def hdl_parameters(self) -> dict[str, int]:
        """The Verilog parameters of the twin (SYNC_DEPTH, CNT_W, ADAPTIVE, PW, ... in ticks)."""
    @property
    def clock_ns(self) -> int: ...
    def signals(self, kind: SignalKind | None = None) -> list[Signal]:
        """The signal table of this core (names and widths from the Rust side)."""
    def copy(self) -> Core: ...
    def __copy__(self) -> Core: ...
    def __deepcopy__(self, memo: object) -> Core: ...

def signal_table(
    kind: SignalKind | None = None, *, sync_depth: int = 2, cnt_width: int = 16
) -> list[Signal]:
    """The signal table for a structural configuration."""

class Coverage:
    """Functional coverage of one run (docs/verification.md), sampled at every edge of a core.

    ``Coverage(core)`` samples the configuration in force in ``core``; ``Coverage(**config)``
    takes the keyword arguments of :class:`Core` instead. ``cov.step(core, **inputs)`` is
    ``core.step(**inputs)`` with the edge sampled.
    """

    def __init__(self, core: Core | None = None, **config: Unpack[_Config]) -> None: ...
    def step(self, core: Core, **inputs: Unpack[_Inputs]) -> Outputs:
        """``core.step(**inputs)`` with the edge sampled; the outputs after the edge."""
    def step_traced(self, core: Core, **inputs: Unpack[_Inputs]) -> Trace:
        """``core.step_traced(**inputs)`` with the edge sampled."""
    def hits(self) -> dict[str, int]:
        """``{bin name: hits}`` for every bin, in the model's order."""
    def closure(self) -> tuple[int, int]:
        """(bins hit at least once, bins that can be hit)."""
    @property
    def edges(self) -> int:
        """Edges sampled so far."""
    @property
    def clock_ns(self) -> int: ...
    def to_json(self, run_id: str, verdict: str = "pass") -> str:
        """The text of ``coverage.json`` for this run."""
    def write(self, path: str | PathLike[str], run_id: str, verdict: str = "pass") -> None:
        """Write ``coverage.json`` (a temporary file renamed into place)."""
    @staticmethod
    def bins() -> list[tuple[str, Literal["point", "cross"], str, str | None]]:
        """Every bin: (name, kind, cite, reason it can never be hit or None)."""
    @staticmethod
    def model() -> str:
        """The model's identity, carried by every coverage file."""
    def __copy__(self) -> Coverage: ...

def merge_coverage(
    paths: list[str | PathLike[str]], out: str | PathLike[str]
) -> tuple[int, int, int]:
    """Merge coverage files into ``out`` as ``pmu50 merge``; (bins hit, reachable bins, runs).
    :class:`CoverageError` (file and reason) or ``OSError``, and nothing is written."""

def export_ucis(path: str | PathLike[str], out: str | PathLike[str]) -> None:
    """Export a ``coverage.json`` file to UCIS 1.0 XML."""

class Pulse:
    """One row of the per-pulse event table (state after a key-off sampling edge)."""

    tick: int
    time_ns: int
    cs: bool
    cc: bool
    hist_s: bool
    hist_c: bool
    cnt_r: int
    si: int
    si_ms: float
    cnt_s: int
    cnt_c: int
    fig17: str
    fig18: str

class PulseRun:
    """Identical pulses: ``first``, then ``count - 1`` more every ``stride`` ticks."""

    first: Pulse
    count: int
    stride: int

class PulseTable:
    """The per-pulse table, run-length encoded: a sequence of :class:`Pulse` built on demand."""

    def __len__(self) -> int: ...
    @overload
    def __getitem__(self, i: int) -> Pulse: ...
    @overload
    def __getitem__(self, i: slice) -> list[Pulse]: ...
    def __iter__(self) -> Iterator[Pulse]: ...
    @property
    def runs(self) -> list[PulseRun]:
        """The run-length rows."""

class Readout:
    """One key-on read-out by the MPU (FIG. 12-13)."""

    tick: int
    time_ns: int
    cnt_s: int
    cnt_c: int
    cnt: int
    q1: int
    q2: int
    quadrant_diff: int
    equation: str
    cnt_a: int
    nr: int
    theta1_deg: float
    theta_m_deg: float
    theta_o_deg: float
    theta_i_deg: float
    true_deg: float
    error_deg: float
    diag: bool
    quadrant_skip: bool
    theta_abnormal: bool
    quadrant_mismatch: bool
    counts_abnormal: bool

class KeyOff:
    tick: int
    true_deg: float
    theta_m_deg: float
    theta_o_deg: float
    theta_i_deg: float

class Check:
    name: str
    ok: bool
    detail: str

class DarkCurrent:
    key_off_ns: int
    vm_on_ns: int
    vs1_on_ns: int
    vs2_on_ns: int
    vp_on_ns: int
    vs2_duty: float | None
    charge_uc: float
    avg_current_ua: float | None

class RunResult:
    """What ``pmu50 run`` prints, as objects; ``str(result)`` is the printed summary."""

    name: str
    ticks: int
    clock_ns: int
    evaluated_ticks: int
    skipped_ticks: int
    pulses: PulseTable
    intervals_ms: list[float]
    readouts: list[Readout]
    keyoffs: list[KeyOff]
    checks: list[Check]
    passed: bool
    dark: DarkCurrent
    final_outputs: Outputs
    final_regs: dict[str, dict[str, int]]
    summary: str
    vcd_path: Path | None
    gtkw_path: Path | None
    log_path: Path | None

class Scenario:
    """A validated scenario file."""

    @staticmethod
    def load(path: str | PathLike[str]) -> Scenario:
        """Read and validate a file; :class:`ScenarioError` (``file:line: ...``) or ``OSError``."""
    @staticmethod
    def from_str(text: str, filename: str = "scenario.toml") -> Scenario:
        """Validate scenario text; ``filename`` appears in errors, its stem is the default name."""
    @property
    def name(self) -> str: ...
    @property
    def description(self) -> str: ...
    @property
    def ticks(self) -> int: ...
    @property
    def clock_ns(self) -> int: ...
    @property
    def core(self) -> dict[str, str | int | bool]:
        """The ``[core]`` configuration: ``Core(**scenario.core)`` is the scenario's core."""
    @property
    def hdl_parameters(self) -> dict[str, int]: ...
    def events(self) -> list[tuple[int, str, object]]:
        """``[(tick, "ig" | "vs2_fault" | "write", value)]``; a write's value is (register,
        address, data)."""
    def run(self, out_dir: str | PathLike[str] | None = None, *, log: bool = False) -> RunResult:
        """Run with the environment; with ``out_dir`` also write the VCD, .gtkw (and .log)."""
