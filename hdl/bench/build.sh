#!/usr/bin/env bash
# Build the Verilator speed harness (hdl/bench/bench.cpp) for the parameters of one vector file.
#
#   hdl/bench/build.sh FILE.vec OUTDIR [--trace | --trace-all]
#
# verilator --cc -O3 (with --trace when asked) and g++ -O3 -march=native of the generated model,
# the harness and the Verilator runtime; the `// param` lines of FILE.vec become -G values. With
# --trace, hdl/bench/trace.vlt limits the dump to the twin's counterparts of the Rust tracer's 65
# signals (inputs, outputs, registers, internals; not the twin's other nets); with --trace-all
# Verilator dumps every variable of the twin (371, as `verilator --trace` does by default). Output:
# OUTDIR/bench (skipped when newer than its sources). Exit 2 on a tool failure.
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/../scripts/common.sh"
VEC="$1"
mkdir -p "$2"
OUT="$(cd "$2" && pwd)"
TRACE="${3:-}"
rtl_files "$HDL/pmu50.f"
ARGS=()
vec_params "$VEC" -G
unset 'ARGS[-1]'   # -GCLOCK_NS: the harness, not the design, has the clock
GS=("${ARGS[@]}")
if [ -x "$OUT/bench" ] && [ -f "$OUT/params" ] && [ "$(cat "$OUT/params")" = "${GS[*]} $TRACE" ]; then
    newer=0
    for s in "${BASH_SOURCE[0]}" "$HDL/scripts/common.sh" "$HDL/bench/bench.cpp" "$HDL/bench/trace.vlt" "${RTL[@]}"; do [ "$s" -nt "$OUT/bench" ] && newer=1; done
    [ $newer = 0 ] && exit 0
fi
rm -rf "$OUT"
mkdir -p "$OUT"
VROOT="$(verilator --getenv VERILATOR_ROOT)"
VFLAGS=(--cc -O3 --x-assign fast --x-initial fast --top-module pmu50 -Mdir "$OUT/obj" "${GS[@]}")
RT=(verilated.cpp verilated_threads.cpp)
TRACE_DEF=0
case "$TRACE" in
    --trace) VFLAGS+=(--trace "$HDL/bench/trace.vlt") ;;
    --trace-all) VFLAGS+=(--trace) ;;
esac
if [ -n "$TRACE" ]; then
    RT+=(verilated_vcd_c.cpp)
    TRACE_DEF=1
fi
verilator "${VFLAGS[@]}" "${RTL[@]}" > "$OUT/verilator.log" 2>&1 || { cat "$OUT/verilator.log" >&2; exit 2; }
CXX=(g++ -std=c++17 -O3 -march=native -I"$VROOT/include" -I"$VROOT/include/vltstd" -DVM_TRACE=$TRACE_DEF -DVM_COVERAGE=0 -DVM_SC=0)
(
    cd "$OUT/obj"
    # the harness and the generated model in one translation unit; the runtime separately
    {
        echo "#include \"$HDL/bench/bench.cpp\""
        for f in Vpmu50*.cpp; do echo "#include \"$f\""; done
    } > unity.cpp
    "${CXX[@]}" -I. -c unity.cpp -o unity.o
    objs=(unity.o)
    for f in "${RT[@]}"; do
        "${CXX[@]}" -I. -c "$VROOT/include/$f" -o "${f%.cpp}.o"
        objs+=("${f%.cpp}.o")
    done
    "${CXX[@]}" "${objs[@]}" -o "$OUT/bench" -lpthread -latomic
) > "$OUT/build.log" 2>&1 || { cat "$OUT/build.log" >&2; exit 2; }
echo "${GS[*]} $TRACE" > "$OUT/params"
