#!/usr/bin/env bash
# Build the Verilator speed harness (hdl/bench/bench.cpp) of `verilator --trace` of every variable
# for `make bench`'s wall-time table (benches/compare.sh), with Verilator's multithreading.
#
#   benches/verilator_threads.sh FILE.vec OUTDIR THREADS
#
# The same build as `hdl/bench/build.sh FILE.vec OUTDIR --trace-all` (verilator --cc -O3 --trace,
# g++ -O3 -march=native, the file's parameters as -G values) plus `--threads THREADS` (Verilator 5
# evaluates the model on that many threads; `--trace-threads` offloads only FST waveforms in this
# version, which the harness does not write), and with the harness's clock the wall clock
# (CLOCK_MONOTONIC for CLOCK_PROCESS_CPUTIME_ID): its `cpu_s=` is then the wall time of its
# replay loop, the file opened and closed. Output: OUTDIR/bench (skipped when newer than its
# sources). Exit 2 on a tool failure.
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/../hdl/scripts/common.sh"
VEC="$1"
mkdir -p "$2"
OUT="$(cd "$2" && pwd)"
THREADS="$3"
case "$THREADS" in
    ''|*[!0-9]*) echo "verilator_threads.sh: THREADS must be a whole number, got '$THREADS'" >&2; exit 2 ;;
esac
rtl_files "$HDL/pmu50.f"
ARGS=()
vec_params "$VEC" -G
unset 'ARGS[-1]'   # -GCLOCK_NS: the harness, not the design, has the clock
GS=("${ARGS[@]}")
STAMP="${GS[*]} --trace-all --threads $THREADS wall-clock"
if [ -x "$OUT/bench" ] && [ -f "$OUT/params" ] && [ "$(cat "$OUT/params")" = "$STAMP" ]; then
    newer=0
    for s in "${BASH_SOURCE[0]}" "$HDL/scripts/common.sh" "$HDL/bench/bench.cpp" "${RTL[@]}"; do [ "$s" -nt "$OUT/bench" ] && newer=1; done
    [ $newer = 0 ] && exit 0
fi
rm -rf "$OUT"
mkdir -p "$OUT"
VROOT="$(verilator --getenv VERILATOR_ROOT)"
VFLAGS=(--cc -O3 --x-assign fast --x-initial fast --top-module pmu50 -Mdir "$OUT/obj" "${GS[@]}" --trace --threads "$THREADS")
RT=(verilated.cpp verilated_threads.cpp verilated_vcd_c.cpp)
verilator "${VFLAGS[@]}" "${RTL[@]}" > "$OUT/verilator.log" 2>&1 || { cat "$OUT/verilator.log" >&2; exit 2; }
CXX=(g++ -std=c++17 -O3 -march=native -I"$VROOT/include" -I"$VROOT/include/vltstd" -DVM_TRACE=1 -DVM_COVERAGE=0 -DVM_SC=0 -DVL_THREADED=1)
(
    cd "$OUT/obj"
    {
        # the harness's replay-loop clock becomes the wall clock
        echo "#include <time.h>"
        echo "#undef CLOCK_PROCESS_CPUTIME_ID"
        echo "#define CLOCK_PROCESS_CPUTIME_ID CLOCK_MONOTONIC"
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
echo "$STAMP" > "$OUT/params"
