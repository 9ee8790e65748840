"""Tests of the coverage proofs (hdl/formal/coverage.py): a bin declared unreachable that the
RTL can reach is reported as a wrong declaration with a witness the model can replay, and a
cover's witness becomes a vector file. Run with `make formal-test`."""

import json
import os
import re
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
KIT = os.path.dirname(HERE)
HDL = os.path.dirname(KIT)
RUN = [sys.executable, os.path.join(KIT, "coverage.py")]


def rtl_copy(tmp_path, block, old, new):
    """The twin's RTL under tmp_path with `old` replaced by `new` in rtl/<block>."""
    dst = tmp_path / "rtl_copy"
    shutil.copytree(os.path.join(HDL, "rtl"), dst / "rtl")
    shutil.copy(os.path.join(HDL, "pmu50.v"), dst / "pmu50.v")
    shutil.copy(os.path.join(HDL, "pmu50.f"), dst / "pmu50.f")
    f = dst / "rtl" / block
    text = f.read_text()
    assert old in text
    f.write_text(text.replace(old, new, 1))
    return str(dst / "pmu50.f")


def run(tmp_path, *args):
    # the proofs on set small only: the structural class sets are test_any_rtl's
    args = ["--sets", "small", "--proof-sets", "small", "--out", str(tmp_path / "out")] + list(args)
    p = subprocess.run(
        RUN + args,
        capture_output=True,
        text=True,
        timeout=1200,
    )
    return p.returncode, p.stdout + p.stderr, tmp_path / "out"


def test_the_twin_proves_its_declared_history_bins_unreachable(tmp_path):
    rc, out, d = run(tmp_path, "--no-covers", "--bins", "history.both")
    doc = json.load(open(d / "coverage.json"))
    st = {b["name"]: b for b in doc["bins"]}
    assert st["fig18.history.both"]["status"] == "proven_unreachable", out
    assert st["fig18.history.both"]["sets"] == ["small"]
    assert rc == 0, out


def test_a_wrong_declaration_is_refuted_with_a_witness(tmp_path):
    # S23 without clearing hist_c: a Cs detection after a Cc one sets both history flops, so
    # the bin fig18.history.both, declared unreachable, can be hit
    f = rtl_copy(
        tmp_path,
        "drive_interval_changing_56b.v",
        "hist_s_n = 1'b1;\n                    hist_c_n = 1'b0;",
        "hist_s_n = 1'b1;",
    )
    # a copy of the twin is another RTL: its internals are bound through the twin's map
    rc, out, d = run(
        tmp_path,
        "--no-covers",
        "--bins",
        "history.both",
        "--rtl",
        f,
        "--map",
        os.path.join(HDL, "pmu50.map.toml"),
    )
    assert rc == 1, out
    assert re.search(r"^fig18\.history\.both\s+wrong_declaration", out, re.M), out
    doc = json.load(open(d / "coverage.json"))
    b = {b["name"]: b for b in doc["bins"]}["fig18.history.both"]
    assert b["status"] == "wrong_declaration"
    vec = open(os.path.join(os.path.dirname(HDL), b["witness"])).read()
    assert "// bin fig18.history.both" in vec and "// param CNT_W 4" in vec
    rows = [ln for ln in vec.splitlines() if not ln.startswith("//")]
    assert len(rows) == b["step"] and all(len(r.split()) == 7 for r in rows)
    # the cross bins of a wrong point declaration are refuted with it
    assert b["proofs"]["small"]["verdict"] == "refuted"


def test_a_port_level_cover_gets_a_witness(tmp_path):
    rc, out, d = run(tmp_path, "--bins", "bus.read.unmapped", "--cover-depth", "8")
    doc = json.load(open(d / "coverage.json"))
    b = {b["name"]: b for b in doc["bins"]}["bus.read.unmapped"]
    assert b["status"] == "witnessed", out
    vec = open(os.path.join(os.path.dirname(HDL), b["witness"])).read()
    rows = [ln.split() for ln in vec.splitlines() if not ln.startswith("//")]
    # the last edge reads an unmapped address with the key on and no write
    assert rows[-1][4] == "0" and int(rows[-1][5], 16) not in (
        list(range(0x00, 0x0D)) + list(range(0x10, 0x15))
    ), rows[-1]
    assert rc == 0, out


def pmu50_bin():
    """The pmu50 command the witness scenarios need ($PMU50, else the checkout's release build)."""
    b = os.environ.get("PMU50") or os.path.join(os.path.dirname(HDL), "target", "release", "pmu50")
    assert os.access(b, os.X_OK), (
        "%s missing: cargo build --release (make formal-test builds it)" % b
    )
    return b


def test_a_bin_beyond_the_cover_depth_is_witnessed_by_its_scenario(tmp_path):
    # a 4-bit counter wraps after 8 counts: far beyond 4 steps; the witness scenario's replay
    # through the twin with the monitor hits it, at its first tick. The output folder is given
    # relative to the working folder, as the make target does.
    p = subprocess.run(
        RUN
        + [
            "--sets",
            "small",
            "--proof-sets",
            "small",
            "--out",
            "rel/out",
            "--bins",
            "cross.wrap_x_cnt_w.cnt_s_up*3_7",
            "--cover-depth",
            "4",
            "--pmu50",
            pmu50_bin(),
            "--deep-scenarios",
            "wrap_w4_clock5us",
        ],
        capture_output=True,
        text=True,
        timeout=1200,
        cwd=tmp_path,
    )
    rc, out, d = p.returncode, p.stdout + p.stderr, tmp_path / "rel" / "out"
    doc = json.load(open(d / "coverage.json"))
    b = {b["name"]: b for b in doc["bins"]}["cross.wrap_x_cnt_w.cnt_s_up*3_7"]
    assert b["status"] == "witnessed" and b["by"] == "simulation", out
    assert b["scenario"] == "hdl/formal/deep/wrap_w4_clock5us.toml"
    assert 8 < b["step"] < 400, b
    assert re.search(r"^deep wrap_w4_clock5us\s+400 ticks, 1 bins witnessed", out, re.M), out
    assert rc == 0, out


def test_a_bin_no_scenario_hits_is_undecided(tmp_path):
    # the CNTr scenario never wraps a counter: the bin stays undecided and the run fails
    rc, out, d = run(
        tmp_path,
        "--bins",
        "cross.wrap_x_cnt_w.cnt_s_up*3_7",
        "--cover-depth",
        "4",
        "--pmu50",
        pmu50_bin(),
        "--deep-scenarios",
        "cnt_r_sat_at_min",
    )
    doc = json.load(open(d / "coverage.json"))
    b = {b["name"]: b for b in doc["bins"]}["cross.wrap_x_cnt_w.cnt_s_up*3_7"]
    assert b["status"] == "undecided", out
    assert "no witness scenario of hdl/formal/deep hits it" in b["tried"]
    assert rc == 1, out


def test_an_unknown_witness_scenario_is_a_setup_error(tmp_path):
    rc, out, _ = run(
        tmp_path,
        "--bins",
        "cross.wrap_x_cnt_w.cnt_s_up*3_7",
        "--cover-depth",
        "2",
        "--pmu50",
        pmu50_bin(),
        "--deep-scenarios",
        "nope",
    )
    assert rc == 2, out
    assert "no witness scenario nope" in out and "wrap_w16" in out, out


def test_the_twins_waiver_claims_are_proven(tmp_path):
    # every waiver of hdl/coverage-waivers.toml states its claim, proven with the lemmas
    rc, out, d = run(tmp_path, "--no-covers", "--bins", "history.both")
    doc = json.load(open(d / "coverage.json"))
    text = open(os.path.join(HDL, "coverage-waivers.toml")).read()
    n = len(re.findall(r"^holds\s*=", text, re.M))
    assert n >= 14 and len(doc["waivers"]) == n, out
    assert all(w["status"] == "proven" for w in doc["waivers"]), out
    assert "%d of %d waivers' claims proven on every set" % (n, n) in out
    assert rc == 0, out


def run_claim(tmp_path, holds):
    """The history bins' proofs with one waiver of t[17:16] claiming `holds`."""
    w = tmp_path / "w.toml"
    w.write_text(
        '[[waiver]]\nfile = "rtl/timing_generator_56.v"\nsignal = "t[17:16]"\n'
        'reason = "a claim under test"\nholds = "%s"\n' % holds
    )
    return run(tmp_path, "--no-covers", "--bins", "history.both", "--waivers", str(w))


def test_a_false_waiver_claim_fails_the_run(tmp_path):
    # a waiver whose reason does not hold (t's top bits are zero, not 01) is refuted
    rc, out, d = run_claim(tmp_path, "t[17:16] == 2'b01")
    doc = json.load(open(d / "coverage.json"))
    assert doc["waivers"][0]["status"] == "refuted", out
    assert "0 of 1 waivers' claims proven" in out and "t[17:16] (refuted)" in out, out
    assert rc == 1, out


def test_a_claim_that_does_not_elaborate_is_a_setup_error(tmp_path):
    rc, out, _ = run_claim(tmp_path, "no_such_net == 1'b0")
    assert rc == 2, out
    assert "a waiver's claim (holds) does not elaborate" in out and "no_such_net" in out, out


def test_cover_verdicts_do_not_depend_on_the_load(tmp_path):
    # the covers' search has an effort budget (steps), not a wall-clock one: the same bins are
    # witnessed at the same steps, with the same witnesses, idle and beside two CPU hogs (the
    # same output folder, so that the witnesses' paths are the same too)
    docs = []
    for hogs in (0, 2):
        procs = [subprocess.Popen(["yes"], stdout=subprocess.DEVNULL) for _ in range(hogs)]
        try:
            rc, out, d = run(
                tmp_path,
                "--bins",
                "fig17.path,bus.write_outcome",
                "--cover-depth",
                "12",
                "--no-deep",
                "--no-waivers",
            )
        finally:
            for q in procs:
                q.kill()
                q.wait()
        doc = json.load(open(d / "coverage.json"))
        assert doc["counts"].get("witnessed", 0) >= 8, out
        doc.pop("digest")
        doc.pop("provenance")
        vecs = sorted((d / "witness").glob("*.vec"))
        assert vecs, out
        doc["witness files"] = {v.name: v.read_text() for v in vecs}
        shutil.rmtree(d)
        docs.append(doc)
    assert docs[0] == docs[1]


def test_a_claim_names_its_waiver_as_pmu50_does(tmp_path):
    """`pmu50 waivers refresh` and the sign-off find a claim's verdict by the waiver's target as
    pmu50 writes it (verif/src/code_cov/waivers.rs, Waiver::what)."""
    sys.path.insert(0, KIT)
    from pmu50_formal.coverage import load_claims

    w = tmp_path / "w.toml"
    w.write_text(
        "\n".join(
            '[[waiver]]\nfile = "rtl/x.v"\n%s\nholds = "a"\n' % t
            for t in [
                'signal = "t[17:16]"',
                "line = 42",
                'line = "40-45"',
                'line = "42"',
                "expr = 27",
                'expr = "27-28"\nterm = "* => 0"',
            ]
        )
    )
    got = [c["what"] for c in load_claims(str(w), ["/d/rtl/x.v"])]
    assert got == [
        "signal t[17:16]",
        "line 42",
        "lines 40-45",
        "line 42",
        "expr 27",
        "expr 27-28 term * => 0",
    ]
