"""Tests of the formal kit (hdl/formal/run.py, the package pmu50_formal): vacuity, engine
agreement, the AIGER cones, the result cache, the counterexample's GTKWave view and the top's
contract it reads. Run with `make formal-test`."""

import os
import re
import shutil
import subprocess
import sys

import pytest

from pmu50_formal import aiger, common, kit

HERE = os.path.dirname(os.path.abspath(__file__))
KIT = os.path.dirname(HERE)
HDL = os.path.dirname(KIT)

RUN = [sys.executable, os.path.join(KIT, "run.py")]


def rtl_copy(tmp_path, extra_in_top):
    """The twin's RTL copied under tmp_path with `extra_in_top` added to module pmu50."""
    dst = tmp_path / "rtl_copy"
    shutil.copytree(os.path.join(HDL, "rtl"), dst / "rtl")
    top = open(os.path.join(HDL, "pmu50.v")).read()
    i = top.rindex("endmodule")
    (dst / "pmu50.v").write_text(top[:i] + extra_in_top + "\n" + top[i:])
    shutil.copy(os.path.join(HDL, "pmu50.f"), dst / "pmu50.f")
    return str(dst / "pmu50.f")


def run_kit(tmp_path, *args):
    p = subprocess.run(
        RUN + ["--sets", "small", "--no-cache", "--out", str(tmp_path / "out")] + list(args),
        capture_output=True,
        text=True,
        timeout=1200,
    )
    return p.returncode, p.stdout + p.stderr


def verdict(out, prop):
    m = re.search(r"^%s\s+small\s+(\w+)" % prop, out, re.M)
    assert m, "no line for %s in:\n%s" % (prop, out)
    return m.group(1)


def test_contradictory_assume_makes_a_mutant_vacuous_not_proven(tmp_path):
    # a contradiction in the RTL under test: no state satisfies it, so every assertion holds
    # trivially; MUT_CNT_C_SIGN would otherwise be refuted by prop_cnt_c_0099
    f = rtl_copy(tmp_path, "    always @(posedge clk) assume (cnt_c == 1 && cnt_c == 2);")
    rc, out = run_kit(
        tmp_path,
        "--rtl",
        f,
        "--mutant",
        "MUT_CNT_C_SIGN",
        "--props",
        "prop_cnt_c_0099,prop_sig_sync",
    )
    assert rc == 1, out
    assert verdict(out, "prop_cnt_c_0099") == "vacuous", out
    assert verdict(out, "prop_sig_sync") == "vacuous", out
    assert re.search(r"^reach_reset_state\s+small\s+unreachable", out, re.M), out
    assert "proven" not in re.findall(r"^prop_\w+\s+small\s+(\w+)", out, re.M)


def test_assume_excluding_an_antecedent_makes_that_proof_vacuous(tmp_path):
    # legal-looking environment assumption that forbids exactly the case rule [0099] is about
    # (a Cc change while Cs = 1): the mutant's property is then proven, but vacuously
    f = rtl_copy(tmp_path, "    always @(posedge clk) assume (!(cs && cmp_c != cc));")
    rc, out = run_kit(
        tmp_path,
        "--rtl",
        f,
        "--mutant",
        "MUT_CNT_C_SIGN",
        "--props",
        "prop_cnt_c_0099,prop_cnt_c_0098",
    )
    assert rc == 1, out
    assert verdict(out, "prop_cnt_c_0099") == "vacuous", out
    assert "reach_cnt_c_0099 unreachable" in out, out
    # the other rule's antecedent is still reachable: a real proof
    assert verdict(out, "prop_cnt_c_0098") == "proven", out
    assert re.search(r"^reach_keyoff_period\s+small\s+reached", out, re.M), out


def test_refuted_property_gtkw_opens_on_the_failing_cycle(tmp_path):
    rc, out = run_kit(tmp_path, "--mutant", "MUT_CNT_C_SIGN", "--props", "prop_cnt_c_0099")
    assert rc == 1, out
    assert verdict(out, "prop_cnt_c_0099") == "refuted", out
    m = re.search(r"failing cycle (\d+)", out)
    assert m, out
    cycle = int(m.group(1))
    d = tmp_path / "out" / "small" / "prop_cnt_c_0099"
    g = (d / "cex.gtkw").read_text()
    start = int(re.search(r"^\[timestart\] (\d+)", g, re.M).group(1))
    zoom = float(re.search(r"^\*(-?[\d.]+) ", g, re.M).group(1))
    marker = int(re.search(r"^\*\S+ -1 (\d+)", g, re.M).group(1))
    assert marker == cycle * 10
    # the failing cycle and up to 8 cycles before it are in view (wave pane 800 px)
    span = 800 * 2**-zoom / 200
    assert start == max(cycle - 8, 0) * 10
    assert start < marker < start + span
    assert "[markername] Aprop_cnt_c_0099 fails" in g
    for sig in [
        "ig",
        "vs2_ok",
        "cmp_s",
        "cmp_c",
        "bus_we",
        "bus_addr[7:0]",
        "bus_wdata[15:0]",
        "cnt_c[3:0]",
        "cs",
        "cc",
    ]:
        assert re.search(r"^pmu50_formal\.%s$" % re.escape(sig), g, re.M), sig
    # the VCD reaches past the marker and the vector file has the stimulus
    assert (d / "cex.vcd").stat().st_size > 0
    assert (d / "cex.vec").read_text().startswith("// pmu50 vectors v1")


def test_gtkw_view_shows_cycles_before_the_failure():
    start, zoom = kit.gtkw_view(560, 10)
    assert start == 480
    span = 800 * 2**-zoom / 200
    assert 560 + 10 <= start + span < 560 + 60
    assert kit.gtkw_view(20, 10)[0] == 0


def test_engines_disagreeing_is_reported():
    assert kit.disagreement({"abc": "refuted", "ric3": "proven"}) == ["abc", "ric3"]
    assert kit.disagreement({"abc": "refuted", "ric3": "refuted"}) == []
    assert kit.disagreement({"abc": "refuted", "ric3": "unknown"}) == []
    assert kit.disagreement({"abc": "proven"}) == []


def test_mutant_table_runs_both_engines(tmp_path):
    if not kit.Ric3().available():
        pytest.skip("rIC3 not built (make formal-tools)")
    p = subprocess.run(
        RUN
        + [
            "--mutants",
            "--only",
            "MUT_SYNC_SHORT,MUT_CNT_R_NO_SAT",
            "--sets",
            "small",
            "--out",
            str(tmp_path / "out"),
        ],
        capture_output=True,
        text=True,
        timeout=1200,
    )
    out = p.stdout + p.stderr
    assert p.returncode == 0, out
    row = next(ln for ln in out.splitlines() if ln.startswith("MUT_SYNC_SHORT"))
    m = re.search(r"refuted abc-(bmc|pdr) @(\d+) .*refuted ric3(-bmc)? @(\d+)", row)
    assert m, row
    # both bounded searches find the shortest trace: the same failing cycle
    assert m.group(2) == m.group(4), row
    # the deep one: each engine's IC3/PDR on the refuter set, 255 quiet pulses deep
    row = next(ln for ln in out.splitlines() if ln.startswith("MUT_CNT_R_NO_SAT"))
    m = re.search(r"prop_si_expand\s+short\s+refuted abc-pdr @(\d+) .*refuted ric3 @(\d+)", row)
    assert m and int(m.group(1)) >= 765 and int(m.group(2)) >= 765, row
    assert "2/2 mutants refuted, 0 engine disagreements" in out


def test_counter_saturation_bug_is_refuted_not_left_unknown(tmp_path):
    # CNTr wraps from 255 to 0 (S9 without its saturation): 255 quiet key-off pulses deep, out
    # of reach of the engines on the small set; the refuter set `short` shows it
    rc, out = run_kit(tmp_path, "--mutant", "MUT_CNT_R_NO_SAT", "--props", "prop_si_expand")
    assert rc == 1, out
    assert verdict(out, "prop_si_expand") == "refuted", out
    line = next(ln for ln in out.splitlines() if ln.startswith("prop_si_expand"))
    m = re.search(r"(ric3|abc-pdr)@short at cycle (\d+) on refuter set short", line)
    assert m, line
    # 255 counts at 3 ticks a pulse at the least: nothing shallower can show this bug
    assert int(m.group(2)) >= 765, line
    assert "unknown" not in re.findall(r"^prop_\w+\s+small\s+(\w+)", out, re.M)
    # the counterexample replays: CNTr goes from 255 to 0 at the failing cycle
    cycle = int(re.search(r"failing cycle (\d+)", line).group(1))
    d = tmp_path / "out" / "short" / "prop_si_expand"
    sigs, _ = common.read_vcd(str(d / "cex.vcd"))
    cnt_r = sigs["pmu50_formal.cnt_r"][1]
    assert common.value_at(cnt_r, (cycle - 1) * 10) == 255
    assert common.value_at(cnt_r, cycle * 10) == 0
    vec = (d / "cex.vec").read_text()
    assert "// param CTH 255" in vec and "// param SI_MIN 3" in vec


def test_undecided_property_fails_the_run_and_says_so(tmp_path):
    rc, out = run_kit(
        tmp_path,
        "--mutant",
        "MUT_CNT_R_NO_SAT",
        "--props",
        "prop_si_expand",
        "--refuters",
        "",
        "--timeout",
        "4",
        "--refute-after",
        "1",
        "--deep",
        "30",
    )
    assert rc == 1, out
    assert verdict(out, "prop_si_expand") == "unknown", out
    # the line says what was tried: the engines' time and the bounded search's depth
    assert re.search(
        r"^prop_si_expand .*open after 4 s; abc-bmc (no failure in \d+ cycles|\w+)", out, re.M
    ), out
    assert "formal: FAILED: 1 property undecided: prop_si_expand (small)" in out, out


def test_refuter_sets_are_legal():
    # spec 4: a counterexample on an illegal parameter set would show no bug of the RTL
    for name, r in kit.REFUTERS.items():
        p = r["params"]
        shortest = p["SI_MIN"] if p["ADAPTIVE"] else p["SI_MAX"]
        assert all(p[k] > 0 for k in ("PS", "SI_MAX", "SI_MIN", "T1", "T2", "CTH", "SMP_ON")), name
        assert p["SI_MIN"] <= p["SI_MAX"] and p["PW"] + p["PI"] >= 1, name
        assert p["PW"] + p["PI"] + p["PS"] < shortest, name
        assert 1 <= p["SYNC_DEPTH"] <= 4 and 2 <= p["CNT_W"] <= 16 and p["CTH"] <= 255, name
        assert name not in common.parameter_sets()


def test_an_abc_witness_is_its_frames_without_the_comment(tmp_path):
    # write_cex -a: the latches, one line per frame, ABC's comment on the last frame's line
    (tmp_path / "abc-pdr.aiw").write_text("000\n0101\n1100 # DONE\n")
    assert kit.witness_inputs(str(tmp_path), "abc-pdr") == ["0101", "1100"]
    assert kit.witness_inputs(str(tmp_path), "abc-bmc") is None  # no file


def test_held_inputs_become_constants():
    # inputs 1, 2; output 0 = AND gate 3 of both
    m = aiger.Aiger(b"aig 3 2 0 1 1\n6\n" + bytes([6 - 4, 4 - 2]))
    assert m.ands == [(4, 2)]
    assert aiger.Aiger(m.held({0: 0})).ands == [(4, 0)]
    assert aiger.Aiger(m.held({0: 1})).ands == [(4, 1)]
    assert aiger.Aiger(m.held({1: 1})).ands == [(2, 1)]
    held = aiger.Aiger(m.held({0: 0, 1: 1}))
    assert held.i == 2 and held.outputs == [6]  # the inputs stay: witness columns keep
    with pytest.raises(aiger.AigerError):
        m.held({2: 0})


def test_cone_keeps_only_what_the_output_reads():
    # inputs 1,2; latches 3 (next = input 1) and 4 (next = latch 4 AND input 2);
    # output 0 = latch 3, output 1 = AND gate 5
    m = aiger.Aiger(b"aig 5 2 2 2 1\n2\n10\n6\n10\n" + bytes([10 - 8, 8 - 4]))
    data, latches = m.cone(m.outputs[0])
    assert data.startswith(b"aig 3 2 1 0 0 1 0\n") and latches == {0: 0}
    data, latches = m.cone(m.outputs[1])
    assert latches == {1: 0}
    again = aiger.Aiger(data)
    assert again.l == 1 and again.a == 1 and again.b == 1 and again.bad == [8]


def test_cache_key_follows_every_file_read(tmp_path):
    a = tmp_path / "a.v"
    a.write_text("module a; endmodule\n")
    k1 = kit.sources_digest([str(a)], [], [], "")
    a.write_text("module a; wire w; endmodule\n")
    k2 = kit.sources_digest([str(a)], [], [], "")
    assert k1 != k2
    assert kit.sources_digest([str(a)], [], [], "MUT_X") != k2
    inc = tmp_path / "inc"
    inc.mkdir()
    (inc / "h.vh").write_text("`define X 1\n")
    k3 = kit.sources_digest([str(a)], [str(inc)], [], "")
    (inc / "h.vh").write_text("`define X 2\n")
    assert kit.sources_digest([str(a)], [str(inc)], [], "") != k3


def test_every_parameter_set_is_legal_by_the_contract():
    # each value within its parameter's legal range, every parameter of the top named once
    from pmu50_formal import coverage

    sets = dict(coverage.parameter_sets())
    sets.update({"refuter " + r: v["params"] for r, v in kit.REFUTERS.items()})
    assert set(sets) >= {"default", "small", "sync1", "w8d4", "refuter short"}
    for name, params in sets.items():
        assert common.illegal_values(params) == [], name
    assert common.illegal_values({**common.default_set(), "CTH": 0}) == [
        "CTH = 0 is outside 1..255"
    ]
    assert common.illegal_values({"NOPE": 1})[0] == "NOPE is not a parameter of the top"


def test_the_contracts_columns_are_the_vector_files(tmp_path):
    # the counterexample's cex.vec and a coverage witness are read by the model: their columns
    # (the contract's inputs and outputs, in order) are those `pmu50 vectors` writes
    pmu50 = os.environ.get("PMU50") or os.path.join(
        os.path.dirname(HDL), "target", "release", "pmu50"
    )
    assert os.access(pmu50, os.X_OK), "%s missing: cargo build --release (make formal-test)" % pmu50
    vec = tmp_path / "x.vec"
    scenario = os.path.join(os.path.dirname(HDL), "scenarios", "fig15a.toml")
    subprocess.run([pmu50, "vectors", scenario, "-o", str(vec)], check=True, capture_output=True)
    header = {}
    for line in vec.read_text().splitlines():
        if not line.startswith("//"):
            break
        key, _, value = line[2:].strip().partition(" ")
        header.setdefault(key, value)
    ins, outs = common.inputs(), common.outputs()
    assert header["columns"] == " ".join(n for n, _ in ins) + " | " + " ".join(outs)
    assert header["fields"] == str(len(ins) + len(outs))
    row = next(line for line in vec.read_text().splitlines() if not line.startswith("//"))
    assert [len(x) for x in row.split()] == [common.digits(n) for n, _ in ins] + [
        common.digits(n) for n in outs
    ]
    # and every parameter line of the vector file is a parameter of the contract at its default
    params = {}
    for line in vec.read_text().splitlines():
        if line.startswith("// param "):
            name, value = line[len("// param ") :].split()
            params[name] = int(value)
    assert params == common.default_set()


def test_an_unreadable_contract_is_a_setup_error(tmp_path):
    bad = tmp_path / "contract.json"
    bad.write_text("{")
    with pytest.raises(common.SetupError, match="cannot read the top's contract .*contract.json"):
        common.contract(str(bad))
    bad.write_text('{"top": "pmu50", "clock": "clk", "reset": "rst_n", "parameters": []}')
    with pytest.raises(common.SetupError, match="contract.json: ports is missing, not list"):
        common.contract(str(bad))
    bad.write_text(
        '{"top": "pmu50", "clock": "clk", "reset": "rst_n", "parameters": [], "ports": '
        '[{"name": "ig", "direction": "in", "width": 1, "max_width": "1"}]}'
    )
    with pytest.raises(common.SetupError, match=r"ports\[0\]\.max_width is '1', not int"):
        common.contract(str(bad))
