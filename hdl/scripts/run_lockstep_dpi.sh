#!/usr/bin/env bash
# Method 2, SystemVerilog/DPI-C variant, with Verilator (--binary --timing): builds
# hdl/tb/lockstep/tb_lockstep_dpi.sv + pmu50_dpi.c + the twin for the vector file's parameters
# (cached per parameter set and mutant in hdl/build/dpi/) and runs it.
#
#   hdl/scripts/run_lockstep_dpi.sh FILE.vec [--mutant MUT_NAME] [--coverage OUT.json [--run-id ID]]
#
# --coverage: the bench samples the functional coverage model at every step through the C ABI
# and writes OUT.json (coverage.json, the merge format of `pmu50 merge`), run id ID (default
# dpi/<vector file name>), verdict pass or fail.
# Exit 0 `PASS ...`, 1 divergence (`MISMATCH tick=...` lines), 2 bad input / build error.
set -uo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/common.sh"
VEC="${1:?usage: run_lockstep_dpi.sh FILE.vec [--mutant MUT] [--coverage OUT.json [--run-id ID]]}"
shift
MUT=none
PLUS=()
RUN_ID="dpi/$(basename "$VEC" .vec)"
COV=""
while [ $# -gt 0 ]; do
    case "$1" in
        --mutant) MUT="${2:?}"; shift 2 ;;
        --coverage) COV="${2:?}"; shift 2 ;;
        --run-id) RUN_ID="${2:?}"; shift 2 ;;
        *) echo "run_lockstep_dpi: unknown option $1" >&2; exit 2 ;;
    esac
done
[ -n "$COV" ] && PLUS+=("+coverage=$COV" "+run_id=$RUN_ID")
LIB="$PMU50_FFI_LIB"
[ -f "$LIB" ] || { echo "run_lockstep_dpi: $LIB missing (cargo build -p pmu50-ffi --release)" >&2; exit 2; }
ARGS=()
vec_params "$VEC" -G

[ "$MUT" != none ] && ARGS+=("+define+$MUT")
rtl_files "$HDL/pmu50.f"
# one build per parameter set, mutant and content of the sources and the model library
KEY=$( (printf '%s\n' "${ARGS[@]}"; cat "$HDL/tb/lockstep/tb_lockstep_dpi.sv" "$HDL/tb/lockstep/pmu50_dpi.c" "$HDL/ffi/include/pmu50.h" "${RTL[@]}" "$LIB") | md5sum | cut -c1-12)
OUT="$HDL/build/dpi/$MUT/$KEY"
if [ ! -x "$OUT/tb" ]; then
    rm -rf "$OUT"; mkdir -p "$OUT"
    verilator --binary --timing -j 2 -Wno-fatal -Wno-lint -Wno-style --top-module tb_lockstep_dpi "${ARGS[@]}" \
        -Mdir "$OUT/obj" -o "$OUT/tb" -CFLAGS "-I$HDL/ffi/include" -LDFLAGS "$LIB -lpthread -ldl -lm" \
        "$HDL/tb/lockstep/tb_lockstep_dpi.sv" "${RTL[@]}" "$HDL/tb/lockstep/pmu50_dpi.c" > "$OUT.build.log" 2>&1 \
        || { tail -30 "$OUT.build.log" >&2; exit 2; }
fi
OUTTXT=$("$OUT/tb" "+vec=$VEC" "${PLUS[@]}" 2>&1)
rc=$?
printf '%s\n' "$OUTTXT"
grep -q '^MISMATCH' <<< "$OUTTXT" && exit 1
[ $rc -ne 0 ] && exit 2
grep -q '^PASS' <<< "$OUTTXT" && exit 0
exit 2
