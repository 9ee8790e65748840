"""The kit on an RTL unlike the twin (hdl/alt_sv: SystemVerilog with a package imported in module
headers, typed parameters, a packed-struct register) and what does not depend on the machine:
the slang front end, the coverage monitor's binding through a map or the ports, per-RTL
waivers, sealed outputs, verdicts under CPU budgets beside a CPU hog. Run with `make
formal-test`."""

import json
import os
import subprocess
import sys
import time
import types

import pytest

from pmu50_formal import bind, common, coverage, frontend

HERE = os.path.dirname(os.path.abspath(__file__))
KIT = os.path.dirname(HERE)
HDL = os.path.dirname(KIT)
ALT = os.path.join(HDL, "alt_sv", "pmu50_alt.f")
ALT_MAP = os.path.join(HDL, "alt_sv", "pmu50_alt.map.toml")
RUN = [sys.executable, os.path.join(KIT, "run.py")]


def table():
    return coverage.load_table()


def test_file_list_is_read_by_pmu50_rtl_files():
    rtl = frontend.read_rtl(ALT)
    assert rtl.files[0].endswith("pmu50_alt_pkg.sv") and rtl.is_sv()
    assert rtl.content_hash.startswith("sha256:")
    assert frontend.choose(rtl, "auto") == "slang"
    twin = frontend.read_rtl(os.path.join(HDL, "pmu50.f"))
    assert frontend.choose(twin, "auto") == "yosys"
    with pytest.raises(common.SetupError, match="unknown front end"):
        frontend.choose(twin, "verific")


def test_bad_file_list_is_refused_with_its_error(tmp_path):
    f = tmp_path / "bad.f"
    f.write_text("missing.sv\n")
    with pytest.raises(common.SetupError, match="missing.sv"):
        frontend.read_rtl(str(f))


def test_alt_sv_passes_properties_through_slang(tmp_path):
    # yosys 0.23 alone stops at `import pmu50_alt_pkg::*;` in a module header
    p = subprocess.run(
        RUN
        + ["--rtl", ALT, "--sets", "small", "--no-cache", "--engines", "abc"]
        + ["--props", "prop_sig_sync,prop_write_accepted,prop_read_params"]
        + ["--out", str(tmp_path / "out"), "--json", str(tmp_path / "formal.json")],
        capture_output=True,
        text=True,
        timeout=1200,
    )
    out = p.stdout + p.stderr
    assert p.returncode == 0, out
    assert "3/3 proven, 0 refuted, 0 vacuous" in out, out
    doc = json.load(open(tmp_path / "formal.json"))
    assert doc["frontend"] == "slang"
    assert doc["provenance"]["rtl"]["hash"] == frontend.read_rtl(ALT).content_hash
    chk = subprocess.run(
        [common.pmu50_binary(), "seal", "--check", str(tmp_path / "formal.json")],
        capture_output=True,
        text=True,
    )
    assert chk.returncode == 0, chk.stdout + chk.stderr
    # an edited verdict is caught by the digest
    text = open(tmp_path / "formal.json").read().replace('"proven"', '"refuted"', 1)
    (tmp_path / "formal.json").write_text(text)
    chk = subprocess.run(
        [common.pmu50_binary(), "seal", "--check", str(tmp_path / "formal.json")],
        capture_output=True,
        text=True,
    )
    assert chk.returncode == 2 and "digest" in chk.stdout + chk.stderr


def test_monitor_dependencies_are_the_cones_of_the_hit_wires():
    inputs, deps = bind.dependencies()
    assert "fig17" in inputs and "si_n" in inputs
    w = {b["name"]: b["wire"] for b in table()["bins"]}
    assert "fig17" in deps[w["fig17.path.s1_no_rise"]]
    assert "CLOCK_NS" in deps[w["config.clock.10us"]]
    # a port-level bin reads ports only
    pb = next(b for b in table()["bins"] if b["port_only"])
    assert all(
        k
        in {s["name"] for s in table()["signals"] if s["source"] == "port"}
        | {"CLOCK_NS", "CNT_W", "SYNC_DEPTH"}
        for k in deps[pb["wire"]]
    )
    # no bin declared unreachable reads the clock period: the clock classes change none of them
    assert not [b for b in table()["bins"] if b["unreachable"] and "CLOCK_NS" in deps[b["wire"]]]


def test_binding_takes_the_map_then_the_ports_and_names_what_is_missing():
    t = table()
    none = bind.bindings(t, {})
    assert none["pw"][0] == "ports" and none["si_n"] == ("next", "si", None)
    assert none["fig17"][0] == "none" and none["fig17"][2] == ("internals", "fig17")
    need = coverage.needs_entries(t, none)
    assert "fig17.path.s1_no_rise" in need
    assert bind.entry_text(need["fig17.path.s1_no_rise"][0][1]).startswith('[internals] "fig17"')
    mapped = bind.bindings(t, bind.read_map(ALT_MAP))
    assert mapped["fig17"] == ("map", "dut.u_adapt.fig17_o", ("internals", "fig17"))
    assert mapped["tmr"] == ("map", "dut.u_timer.timer_q", ("registers", "timing_generator.tmr"))
    assert not coverage.needs_entries(t, mapped)


def test_bad_map_is_refused(tmp_path):
    f = tmp_path / "m.toml"
    f.write_text('[registrs]\n"x" = "pmu50.a"\n')
    with pytest.raises(common.SetupError, match="not a section"):
        bind.read_map(str(f))


def test_twin_waivers_never_apply_to_another_rtl():
    a = types.SimpleNamespace(no_waivers=False, waivers="")
    assert coverage.waiver_file(a, twin=True) == coverage.WAIVERS
    assert coverage.waiver_file(a, twin=False) == ""
    a.waivers = coverage.WAIVERS
    with pytest.raises(common.SetupError, match="twin only"):
        coverage.waiver_file(a, twin=False)


def test_class_sets_cover_every_structural_class():
    cs = coverage.class_sets()
    assert len(cs) == 32
    assert {p["SYNC_DEPTH"] for p in cs.values()} == {1, 2, 3, 4}
    assert {p["CNT_W"] for p in cs.values()} == {2, 4, 8, 16}
    assert {p["ADAPTIVE"] for p in cs.values()} == {0, 1}
    for p in cs.values():
        assert not common.illegal_values(p), p
    assert coverage.set_list("small,classes", "--sets")[0] == "small"
    with pytest.raises(common.SetupError, match="unknown parameter sets"):
        coverage.set_list("d5w2a0", "--sets")


def test_cpu_limit_stops_a_busy_process(tmp_path):
    rc = common.run([sys.executable, "-c", "while True: pass"], str(tmp_path), "spin.log", cpu=1)
    assert rc is None


def test_verdicts_do_not_depend_on_the_load(tmp_path):
    # the same properties, cold, once on their own and once beside two CPU hogs: the same file
    args = ["--rtl", os.path.join(HDL, "pmu50.f"), "--sets", "small", "--no-cache"]
    args += ["--engines", "abc", "--props", "prop_si_expand,prop_write_accepted,prop_sig_sync"]
    docs = []
    for tag, hogs in (("idle", 0), ("loaded", 2)):
        procs = [subprocess.Popen(["yes"], stdout=subprocess.DEVNULL) for _ in range(hogs)]
        try:
            p = subprocess.run(
                RUN
                + args
                + ["--out", str(tmp_path / tag), "--json", str(tmp_path / (tag + ".json"))],
                capture_output=True,
                text=True,
                timeout=1200,
            )
        finally:
            for q in procs:
                q.kill()
                q.wait()
        assert p.returncode == 0, p.stdout + p.stderr
        d = json.load(open(tmp_path / (tag + ".json")))
        d.pop("digest")
        d.pop("provenance")
        docs.append(d)
    assert docs[0] == docs[1]


def test_a_stopped_run_leaves_no_engine_behind(tmp_path):
    # engines run in sessions of their own; SIGTERM to the kit stops them too
    pidfile = tmp_path / "engine.pid"
    script = (
        "import sys; from pmu50_formal import kit\n"
        "class Sleeper(kit.Engine):\n"
        "    name = 'sleeper'\n"
        "    def argv(self, aig, timeout):\n"
        "        return ['sh', '-c', 'echo $$ > %s; exec sleep 300']\n"
        "kit.stop_engines_on_sigterm()\n"
        "kit.run_portfolio([kit.Task(Sleeper(), 'x.aig', %r)], 600)\n" % (pidfile, str(tmp_path))
    )
    p = subprocess.Popen([sys.executable, "-c", script], env=dict(os.environ, PYTHONPATH=KIT))
    for _ in range(200):
        if pidfile.exists() and pidfile.read_text().strip():
            break
        time.sleep(0.05)
    engine = int(pidfile.read_text())
    p.terminate()
    assert p.wait(timeout=30) == 128 + 15
    for _ in range(100):
        try:
            os.kill(engine, 0)
        except ProcessLookupError:
            break
        time.sleep(0.05)
    else:
        os.kill(engine, 9)
        pytest.fail("the engine outlived the kit")


def test_lemmas_that_induction_leaves_open_go_to_the_engines(tmp_path):
    # hdl/alt_sv with a map that names its internals but not its registers: the lemmas then
    # read the parameter registers as the port view rebuilds them from the bus, and the RTL's
    # own registers (its packed cfg_q, which nothing binds) may differ from them in a state no
    # trace reaches, from which the inductive step fails. The engines decide the lemmas
    # k-induction left open (ABC scorr here, pdr or rIC3 where it does not), and the bins that
    # need them are proven again with them assumed.
    text = open(ALT_MAP).read()
    m = tmp_path / "internals.map.toml"
    m.write_text(text[text.index("[internals]") :])
    p = subprocess.run(
        [sys.executable, os.path.join(KIT, "coverage.py"), "--rtl", ALT, "--map", str(m)]
        + ["--proof-sets", "d1w2a1", "--no-covers", "--no-cache", "--cpu-limit", "2"]
        + ["--bins", "fig17_x_cnt_r.fixed", "--out", str(tmp_path / "out")],
        capture_output=True,
        text=True,
        timeout=1200,
    )
    out = p.stdout + p.stderr
    lemma = {
        ln.split()[0]: ln for ln in out.splitlines() if ln.startswith("lemma_") and "d1w2a1" in ln
    }
    # not 3-inductive over the port view's registers, proven by the engines
    for n in ("lemma_cnt_r_at_max", "lemma_fixed_cnt_r"):
        assert " proven (scorr" in lemma[n] or " proven (abc-pdr" in lemma[n], out
    doc = json.load(open(tmp_path / "out" / "coverage.json"))
    st = {b["name"]: b for b in doc["bins"] if b["name"].startswith("cross.fig17_x_cnt_r.fixed")}
    assert len(st) == 4 and all(b["status"] == "proven_unreachable" for b in st.values()), out
    assert p.returncode == 0, out
