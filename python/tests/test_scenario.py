"""pmu50.Scenario: loading, errors with file:line, runs with the CLI's summary and files."""

from __future__ import annotations

from pathlib import Path

import pytest

import pmu50

from conftest import DAYS, PER_TICK, ROOT, SCENARIOS, cli


def by_name(name: str) -> Path:
    return ROOT / "scenarios" / f"{name}.toml"


def test_load_and_properties():
    sc = pmu50.Scenario.load(by_name("fig15a"))
    assert sc.name == "fig15a" and sc.clock_ns == 10_000 and sc.ticks == 4800
    assert sc.description
    assert pmu50.Core(**sc.core).hdl_parameters == sc.hdl_parameters
    assert sc.events() == []
    ev = pmu50.Scenario.load(ROOT / "hdl" / "scenarios" / "hdl_bus.toml").events()
    assert {kind for _, kind, _ in ev} >= {"ig", "write"}
    assert [t for t, _, _ in ev] == sorted(t for t, _, _ in ev)
    name, addr, data = next(v for _, kind, v in ev if kind == "write")
    assert dict((n, a) for n, a, _, _ in pmu50.REGISTER_MAP)[name] == addr and 0 <= data <= 0xFFFF


@pytest.mark.parametrize("scenario", PER_TICK, ids=[p.stem for p in PER_TICK])
def test_run_summary_is_the_clis(scenario: Path, tmp_path: Path):
    r = pmu50.Scenario.load(scenario).run()
    out = cli("run", str(scenario), "--out-dir", str(tmp_path), check=False)
    assert out.returncode == (0 if r.passed else 1)
    # The CLI's lines about the waveform (its trace level, the files written) follow the summary;
    # `run()` without a folder writes no waveform.
    printed = out.stdout.split("\n   trace = ")[0].split("\n   wrote ")[0].rstrip()
    assert r.summary.rstrip() == printed
    assert str(r) == r.summary
    # the Python objects carry the same figures as the text
    assert f"{len(r.pulses)} key-off pulses" in r.summary
    if r.intervals_ms:
        assert " -> ".join(f"{v:.1f}" for v in r.intervals_ms) in r.summary
    for c in r.checks:
        assert f"check {c.name:<20} {'PASS' if c.ok else 'FAIL'}  {c.detail}" in r.summary
    assert r.passed == all(c.ok for c in r.checks)


def test_the_parked_days_run_with_skips():
    """scenarios/park_30d.toml: 30 days in about a second, the CLI's summary without a VCD."""
    parked = [p for p in SCENARIOS if p not in PER_TICK]
    for p in parked:
        sc = pmu50.Scenario.load(p)
        assert sc.ticks > DAYS
        r = sc.run()
        assert r.passed, r.summary
        assert r.skipped_ticks > 0 and r.evaluated_ticks + r.skipped_ticks <= r.ticks
        assert r.readouts and r.dark.key_off_ns > 0
        assert f"{len(r.pulses)} key-off pulses" in r.summary
        # hundreds of millions of pulses, a short run-length table, rows built on demand
        assert len(r.pulses) > 100_000_000 and len(r.pulses.runs) < 100_000
        last = r.pulses[-1]
        assert last.tick <= r.ticks and last.si_ms == pytest.approx(r.intervals_ms[-1])


def test_pulse_table_rows_are_its_runs():
    r = pmu50.Scenario.load(by_name("keyoff_turns")).run()
    rows = list(r.pulses)
    assert len(rows) == len(r.pulses) == sum(run.count for run in r.pulses.runs)
    k = 0
    for run in r.pulses.runs:
        for j in range(run.count):
            row = rows[k]
            assert row.tick == run.first.tick + j * run.stride
            assert (row.si, row.cnt_s, row.cnt_c, row.fig17) == (
                run.first.si,
                run.first.cnt_s,
                run.first.cnt_c,
                run.first.fig17,
            )
            k += 1
    assert [p.tick for p in r.pulses[3:9:2]] == [p.tick for p in rows[3:9:2]]
    assert r.pulses[-1].tick == rows[-1].tick
    with pytest.raises(IndexError, match="out of range"):
        r.pulses[len(rows)]


def test_fig15a_pulses_and_intervals():
    r = pmu50.Scenario.load(by_name("fig15a")).run()
    assert r.passed and r.checks
    assert r.intervals_ms[0] == pytest.approx(6.6)
    p = r.pulses[0]
    assert p.si_ms == pytest.approx(p.si * r.clock_ns / 1e6)
    assert p.fig17 in (
        "S1NoRise",
        "S5AtMin",
        "S6Shorten",
        "S7AtMax",
        "S9Count",
        "S10Expand",
        "Fixed",
    )
    assert [q.tick for q in r.pulses] == sorted(q.tick for q in r.pulses)
    assert r.final_outputs.si == r.final_regs["drive_interval"]["si"]
    assert r.evaluated_ticks <= r.ticks


def test_readouts_and_dark_current():
    r = pmu50.Scenario.load(by_name("keyoff_turns")).run()
    assert r.readouts, "keyoff_turns reads the angle out at key-on"
    for k in r.readouts:
        assert k.error_deg == pytest.approx(k.theta_m_deg - k.true_deg, abs=1e-9)
        assert k.cnt == k.cnt_s + k.cnt_c
        assert k.equation in ("Eq1", "Eq2", "Eq3")
    d = r.dark
    assert d.key_off_ns > 0 and 0 < d.vs2_duty < 1
    assert d.vs2_duty == pytest.approx(d.vs2_on_ns / d.key_off_ns)
    assert d.avg_current_ua > 0
    assert f"Vs2 duty {d.vs2_duty * 100:.2f} %" in r.summary


def test_run_writes_the_clis_files(tmp_path: Path):
    sc = by_name("fig15a")
    r = pmu50.Scenario.load(sc).run(tmp_path / "py", log=True)
    assert r.vcd_path == tmp_path / "py" / "fig15a.vcd"
    assert r.gtkw_path.exists() and r.log_path.exists()
    cli("run", str(sc), "--out-dir", str(tmp_path / "cli"), "--log")
    for ext in ("vcd", "log"):
        assert (tmp_path / "py" / f"fig15a.{ext}").read_bytes() == (
            tmp_path / "cli" / f"fig15a.{ext}"
        ).read_bytes(), ext
    # without files: the same figures (fast-forward on)
    plain = pmu50.Scenario.load(sc).run()
    assert plain.vcd_path is None and plain.summary == r.summary


def test_from_str_default_name_and_filename():
    sc = pmu50.Scenario.from_str('duration = "1 ms"\n')
    assert sc.name == "scenario" and sc.ticks == 100
    sc = pmu50.Scenario.from_str('duration = "1 ms"\n', filename="dir/my_case.toml")
    assert sc.name == "my_case"
    r = sc.run()
    assert r.ticks == 100 and r.passed and r.checks == []


BAD = [
    (
        'duration = "10 ms"\n[core]\nt2 = "1.105 ms"\n',
        "bad.toml:3: `core.t2`: core.t2 = 1.105 ms is not a whole number of clock ticks",
    ),
    (
        'duration = "10 ms"\n[[events]]\nat = "1 ms"\nwrite = { reg = "T2", value = 110 }\n',
        "bad.toml:3: `events[0].write`: the key is off at this time",
    ),
    (
        'duration = "10 ms"\n[[events]]\nat = "1 ms"\nig = true\n'
        '[[events]]\nat = "2 ms"\nwrite = { reg = "T9", value = 1 }\n',
        "bad.toml:7: `events[1].write.reg`: unknown register `T9`; registers are ID, VERSION",
    ),
    ("duration = 10\n", "bad.toml:1:12: invalid type: integer `10`, expected a string"),
    ('duration = "10 ms"\nfoo = 1\n', "bad.toml:2:1: unknown field `foo`"),
]


@pytest.mark.parametrize("text,start", BAD, ids=range(len(BAD)))
def test_errors_name_file_line_and_field(text: str, start: str, tmp_path: Path):
    with pytest.raises(pmu50.ScenarioError) as e:
        pmu50.Scenario.from_str(text, "bad.toml")
    assert str(e.value).startswith(start), str(e.value)
    assert isinstance(e.value, ValueError)
    # the same message as the CLI for the same file
    f = tmp_path / "bad.toml"
    f.write_text(text)
    with pytest.raises(pmu50.ScenarioError) as e2:
        pmu50.Scenario.load(f)
    out = cli("check", str(f), check=False)
    assert out.returncode == 2
    assert out.stderr.strip() == f"error: {e2.value}"


def test_missing_file_is_an_os_error(tmp_path: Path):
    with pytest.raises(OSError, match="cannot read the scenario"):
        pmu50.Scenario.load(tmp_path / "nope.toml")


def test_unwritable_out_dir_is_a_simulation_error(tmp_path: Path):
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(pmu50.SimulationError):
        pmu50.Scenario.load(by_name("fig15a")).run(blocker / "sub")
