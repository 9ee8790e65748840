#!/usr/bin/env bash
# The `sim` target of hdl/pmu50.core through FuseSoC, as an HDL team runs it (make fusesoc, in
# make test-long): for each simulator (Icarus, Verilator --binary --timing), the vector files of
# the shipped scenarios fig15a, fig16 and keyoff_turns (default parameters, the target's) replay
# through hdl/tb/tb_vectors.v and pass; a copy of fig15a with one expected output bit flipped
# fails with a MISMATCH line naming that tick and signal.
# Exit 0 when all hold, 1 otherwise, 2 on a setup failure.
set -uo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/scripts/common.sh"
FUSESOC="${FUSESOC:-$ROOT/target/venv/bin/fusesoc}"
W="$HDL/build/fusesoc"
fail() { echo "fusesoc_sim: FAIL: $*" >&2; exit 1; }
[ -x "$PMU50" ] || { echo "fusesoc_sim: $PMU50 missing (cargo build --release)" >&2; exit 2; }
[ -x "$FUSESOC" ] || { echo "fusesoc_sim: $FUSESOC missing (make target/venv/.formal)" >&2; exit 2; }
rm -rf "$W"; mkdir -p "$W"
SCENARIOS=(fig15a fig16 keyoff_turns)
for s in "${SCENARIOS[@]}"; do
    "$PMU50" vectors "$ROOT/scenarios/$s.toml" -o "$W/$s.vec" > /dev/null || { echo "fusesoc_sim: pmu50 vectors $s failed" >&2; exit 2; }
done
# The bad copy: the first data line's expected `si` (by the header's `// columns`) + 1.
python3 - "$W/fig15a.vec" "$W/bad.vec" <<'PY' || { echo "fusesoc_sim: could not make the bad vector file" >&2; exit 2; }
import sys
lines = open(sys.argv[1]).read().split("\n")
cols = next(l for l in lines if l.startswith("// columns ")).split()[2:]
cols.remove("|")
k = next(i for i, l in enumerate(lines) if l and not l.startswith("//"))
f = lines[k].split()
f[cols.index("si")] = "%04x" % ((int(f[cols.index("si")], 16) + 1) & 0xFFFF)
lines[k] = " ".join(f)
open(sys.argv[2], "w").write("\n".join(lines))
PY
cmp -s "$W/fig15a.vec" "$W/bad.vec" && { echo "fusesoc_sim: could not make the bad vector file" >&2; exit 2; }

for tool in icarus verilator; do
    for s in "${SCENARIOS[@]}"; do
        log="$W/$tool-$s.log"
        ( cd "$W" && "$FUSESOC" --cores-root "$HDL" run --build-root "$W/build-$tool" --target=sim --tool=$tool \
              pmu50:core:pmu50 --vec="$W/$s.vec" ) > "$log" 2>&1
        rc=$?
        n=$(($(grep -vc '^//' "$W/$s.vec")))
        grep -q "^PASS ticks=$n\$" "$log" && [ $rc -eq 0 ] || { tail -n 20 "$log"; fail "$tool: $s did not pass (exit $rc, log $log)"; }
        echo "fusesoc_sim: $tool $s: PASS ticks=$n"
    done
    log="$W/$tool-bad.log"
    ( cd "$W" && "$FUSESOC" --cores-root "$HDL" run --build-root "$W/build-$tool" --target=sim --tool=$tool \
          pmu50:core:pmu50 --vec="$W/bad.vec" ) > "$log" 2>&1
    rc=$?
    [ $rc -ne 0 ] || fail "$tool: the flipped vector passed (exit 0)"
    grep -q "^MISMATCH tick=1 signal=si " "$log" || { tail -n 20 "$log"; fail "$tool: no MISMATCH at tick 1 on si (log $log)"; }
    echo "fusesoc_sim: $tool flipped vector: $(grep -m1 '^MISMATCH' "$log") (exit $rc)"
done
echo "fusesoc_sim: PASS (Icarus and Verilator, ${#SCENARIOS[@]} scenarios and a flipped vector each)"
