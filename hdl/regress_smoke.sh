#!/usr/bin/env bash
# `pmu50 regress` against an RTL, as an HDL team runs it (run by `make test`):
#   1. a directed regression of the Verilog twin on Verilator: every seed passes;
#   2. a copy of the twin with one bug planted (MUT_CNT_C_SIGN, hdl/mutants.txt) given with
#      --rtl: the regression fails (exit 1) in one signature, shrunk into failures/<signature>/,
#      its command reproduces it, its save file marks the first divergence, and GTKWave-ready
#      files are valid (pmu50 diff reads them);
#   3. on Icarus the twin passes, and an RTL that hangs fails each seed at the time limit;
#   4. the report renders in headless Chromium (the DOM has the coverage, the failure with the
#      picture of its divergence, and the curve; a screenshot is written to
#      hdl/build/regress_smoke/report.png).
# Exit 0 when all hold, 1 otherwise, 2 on a setup failure.
set -uo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/scripts/common.sh"
W="$HDL/build/regress_smoke"
SEEDS=${SEEDS:-12}
fail() { echo "regress_smoke: FAIL: $*" >&2; exit 1; }
[ -x "$PMU50" ] || { echo "regress_smoke: $PMU50 missing (cargo build --release)" >&2; exit 2; }
rm -rf "$W"; mkdir -p "$W"
PIN=(--sync-depth 2 --cnt-width 8)

# 1. the twin
"$PMU50" regress --directed --iterations "$SEEDS" --dut verilator "${PIN[@]}" --out "$W/twin" > "$W/twin.log" 2>&1
rc=$?
cat "$W/twin.log"
[ $rc -eq 0 ] || fail "the twin does not pass its regression (exit $rc)"

# 2. a planted bug
mkdir -p "$W/mut/rtl"
cp "$HDL"/rtl/*.v "$W/mut/rtl/"; cp "$HDL/pmu50.v" "$HDL/pmu50.f" "$W/mut/"
sed -i '1i `define MUT_CNT_C_SIGN' "$W/mut/rtl/updown_counter_58cd.v"
"$PMU50" regress --directed --iterations "$SEEDS" --dut verilator --rtl "$W/mut/pmu50.f" "${PIN[@]}" --out "$W/mut_run" > "$W/mut.log" 2>&1
rc=$?
cat "$W/mut.log"
[ $rc -eq 1 ] || fail "the planted bug was not found (exit $rc, expected 1)"
n=$(ls -d "$W"/mut_run/failures/*/ 2>/dev/null | wc -l)
[ "$n" -ge 1 ] || fail "no failure folder"
# one root cause, one signature: the counter's error, whether or not the count diagnosis trips
# on the same edge and whichever FIG. path the cycle took (verif/src/check.rs, Failure::signature)
[ "$n" -eq 1 ] || fail "the one planted bug landed in $n signatures: $(ls "$W"/mut_run/failures | tr '\n' ' ')"
for d in "$W"/mut_run/failures/*/; do
    for f in repro.toml command.txt failure.txt repro.vcd repro.gtkw divergence.svg; do [ -s "$d/$f" ] || fail "$d$f missing"; done
    # the picture: the diverging signal as the model and as the DUT (its trace) have it
    grep -q '(model)' "$d/divergence.svg" && grep -q '(DUT)' "$d/divergence.svg" && grep -q '#c00000' "$d/divergence.svg" \
        || fail "$d/divergence.svg does not show the model's and the DUT's values with the divergence marked"
    grep -q '^  gtkwave ' "$d/failure.txt" || fail "$d/failure.txt has no command that opens the waves"
    grep -q '^\[markername\].*first divergence' "$d/repro.gtkw" || grep -q 'first divergence' "$d/repro.gtkw" || fail "$d/repro.gtkw has no marker at the divergence"
    cmd=$(cat "$d/command.txt")
    out=$(cd "$ROOT" && PATH="$ROOT/target/release:$PATH" bash -c "$cmd" 2>&1); rc=$?
    echo "$out" | head -2
    [ $rc -eq 1 ] || fail "the repro command did not reproduce the failure (exit $rc): $cmd"
    "$PMU50" diff "$d/repro.vcd" "$d/repro.vcd" > /dev/null || fail "$d/repro.vcd is not a valid waveform"
    ticks=$(sed -n 's/^duration = "\([0-9]*\) us"/\1/p' "$d/repro.toml")
    echo "shrunk repro: $(grep -c '^\[\[events\]\]' "$d/repro.toml") events, ${ticks} us"
done

# 2b. an RTL that ends the simulation ($fatal at key on) takes its DUT worker down, not the
#     regression: each seed fails with the reason and the next one gets a new worker
mkdir -p "$W/fatal/rtl"
cp "$HDL"/rtl/*.v "$W/fatal/rtl/"; cp "$HDL/pmu50.f" "$W/fatal/"
sed 's|^endmodule|    always @(posedge clk) if (sig) $fatal(1, "planted fatal");\nendmodule|' "$HDL/pmu50.v" > "$W/fatal/pmu50.v"
"$PMU50" regress --start-seed 3 --iterations 3 --dut verilator --rtl "$W/fatal/pmu50.f" "${PIN[@]}" --no-triage --out "$W/fatal_run" > "$W/fatal.log" 2>&1
rc=$?
[ $rc -eq 1 ] || { cat "$W/fatal.log"; fail "an RTL that calls \$fatal: exit $rc, expected 1"; }
[ "$(grep -cE '"verdict":"fail".*the DUT (crashed|ended its process).*planted fatal' "$W/fatal_run/results.jsonl")" -eq 3 ] \
    || { cat "$W/fatal_run/results.jsonl"; fail "the seeds of an RTL that calls \$fatal do not say why"; }
echo "verilator: an RTL that calls \$fatal fails each of 3 seeds with its message"

# 3. Icarus: the twin passes; an RTL that hangs fails its seeds at the time limit, and the
#    regression goes on and ends (nothing of the hung simulator is left running)
"$PMU50" regress --start-seed 3 --iterations 2 --dut icarus --out "$W/iv" > "$W/iv.log" 2>&1 \
    || { cat "$W/iv.log"; fail "the twin on Icarus does not pass"; }
mkdir -p "$W/hang/rtl"
cp "$HDL"/rtl/*.v "$W/hang/rtl/"; cp "$HDL/pmu50.f" "$W/hang/"
sed 's|^endmodule|    always @(posedge clk) if (ig) while (1) begin end  // planted hang\nendmodule|' "$HDL/pmu50.v" > "$W/hang/pmu50.v"
"$PMU50" regress --start-seed 3 --iterations 2 --dut icarus --rtl "$W/hang/pmu50.f" --timeout 5 --no-triage --out "$W/hang_run" > "$W/hang.log" 2>&1
rc=$?
[ $rc -eq 1 ] || { cat "$W/hang.log"; fail "a hanging RTL: exit $rc, expected 1"; }
[ "$(grep -c 'did not finish within the per-seed time limit of 5 s' "$W/hang_run/results.jsonl")" -eq 2 ] || fail "the hung seeds do not say why"
pgrep -f "$W/hang" > /dev/null && fail "the hung simulator is still running"
echo "icarus: the twin passes; a hanging RTL fails both seeds at the 5 s limit"

# 4. the report in a browser
if command -v chromium > /dev/null; then
    timeout 120 chromium --headless --no-sandbox --disable-gpu --dump-dom "file://$W/mut_run/report.html" > "$W/dom.html" 2> /dev/null
    grep -q 'Failures by signature' "$W/dom.html" && grep -q '<svg' "$W/dom.html" && grep -q 'cross.fig17_x_fig18' "$W/dom.html" \
        && grep -q 'failures/dut-' "$W/dom.html" || fail "the report's DOM in Chromium lacks the failures, curve or crosses"
    grep -q 'class="picture"' "$W/dom.html" && grep -q 'cnt_c (DUT)' "$W/dom.html" || fail "the report's DOM lacks the picture of the divergence"
    timeout 120 chromium --headless --no-sandbox --disable-gpu --window-size=1280,1600 --screenshot="$W/report.png" "file://$W/mut_run/report.html" > /dev/null 2>&1
    [ -s "$W/report.png" ] || fail "no screenshot"
else
    echo "regress_smoke: chromium is not installed (make deps installs it)" >&2; exit 2
fi
echo "regress_smoke: ok (twin passes $SEEDS seeds; the planted MUT_CNT_C_SIGN is found, shrunk and reproduced; the report renders)"
