#!/usr/bin/env bash
# Build the Verilator lockstep testbench for one (mutant, SYNC_DEPTH, CNT_W).
#
#   hdl/scripts/build_lockstep.sh [MUTANT|none] [SYNC_DEPTH] [CNT_W] [exe|lib]
#
# exe (default): hdl/build/lockstep/<MUTANT>_<SYNC_DEPTH>_<CNT_W>/lockstep, the bench of
#   hdl/tb/lockstep/lockstep.cpp that replays a vector file against the model's C library; needs
#   target/release/libpmu50_ffi.a (cargo build -p pmu50-ffi --release).
# lib: hdl/build/lockstep/lib_<MUTANT>_<SYNC_DEPTH>_<CNT_W>/libpmu50_dut.so, the RTL alone behind
#   the C interface of hdl/tb/lockstep/dut_lib.cpp, which `pmu50 regress --dut verilator` loads
#   and steps in lockstep with the model in memory.
# Either is skipped when up to date. The Verilator runtime (verilated.cpp ...) is compiled once
# per kind into hdl/build/lockstep/_runtime (_runtime_pic for lib) and shared by every build.
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/common.sh"
MUT="${1:-none}"
SD="${2:-2}"
W="${3:-16}"
KIND="${4:-exe}"
BUILD="${PMU50_BUILD_DIR:-$HDL/build}"
LIB="$ROOT/target/release/libpmu50_ffi.a"
case "$KIND" in
exe)
    OUT="$BUILD/lockstep/${MUT}_${SD}_${W}"
    TARGET="$OUT/lockstep"
    TB="$HDL/tb/lockstep/lockstep.cpp"
    [ -f "$LIB" ] || { echo "build_lockstep: $LIB missing (cargo build -p pmu50-ffi --release)" >&2; exit 2; }
    ;;
lib)
    OUT="$BUILD/lockstep/lib_${MUT}_${SD}_${W}"
    TARGET="$OUT/libpmu50_dut.so"
    TB="$HDL/tb/lockstep/dut_lib.cpp"
    LIB=""
    ;;
*) echo "build_lockstep: kind \`$KIND\` is not exe or lib" >&2; exit 2 ;;
esac

rtl_files
SRCS=("${BASH_SOURCE[0]}" "$HDL/scripts/common.sh" "$FLIST" "${RTL[@]}" "$HDL/tb/lockstep/lockstep.vlt" "$TB" "$HDL/tb/lockstep/twin_access.h" "$HDL/ffi/include/pmu50.h" ${LIB:+"$LIB"})
if [ -f "$TARGET" ]; then
    newer=0
    for s in "${SRCS[@]}"; do [ "$s" -nt "$TARGET" ] && newer=1; done
    [ $newer = 0 ] && exit 0
fi

DEFS=()
[ "$MUT" != none ] && DEFS+=("+define+$MUT")

VROOT="$(verilator --getenv VERILATOR_ROOT)"
RT="$BUILD/lockstep/_runtime"
CXXFLAGS=(-std=c++17 -O1 -I"$VROOT/include" -I"$VROOT/include/vltstd" -DVM_TRACE=0 -DVM_COVERAGE=0)
if [ "$KIND" = lib ]; then
    RT="$BUILD/lockstep/_runtime_pic"
    # -O2: the library is stepped for every seed of a regression, built once per parameter pair
    CXXFLAGS=(-std=c++17 -O2 -fPIC -fvisibility=hidden -I"$VROOT/include" -I"$VROOT/include/vltstd" -DVM_TRACE=0 -DVM_COVERAGE=0)
fi
# Verilator runtime, once.
mkdir -p "$RT"
if [ ! -f "$RT/libvlrt.a" ]; then
    (cd "$RT" && for f in verilated.cpp verilated_threads.cpp; do
        g++ "${CXXFLAGS[@]}" -c "$VROOT/include/$f" -o "${f%.cpp}.o"
    done && ar rcs libvlrt.a verilated.o verilated_threads.o)
fi

rm -rf "$OUT"
mkdir -p "$OUT"
verilator --cc -O3 --x-assign fast --x-initial fast --top-module pmu50 -Mdir "$OUT/obj" \
    -GSYNC_DEPTH="$SD" -GCNT_W="$W" "${DEFS[@]}" \
    "$HDL/tb/lockstep/lockstep.vlt" "${RTL[@]}" > "$OUT/verilator.log" 2>&1 \
    || { cat "$OUT/verilator.log" >&2; exit 2; }
(
    cd "$OUT/obj"
    # one translation unit: the testbench and every generated file (the headers dominate the
    # compile time, so this is ~4x faster than one g++ per file)
    {
        echo "#include \"$TB\""
        for f in Vpmu50*.cpp; do echo "#include \"$f\""; done
    } > unity.cpp
    g++ "${CXXFLAGS[@]}" -I. -I"$HDL/ffi/include" -DPMU50_SYNC_DEPTH="$SD" -DPMU50_CNT_W="$W" \
        -DPMU50_MUTANT="\"$MUT\"" -c unity.cpp -o unity.o
    if [ "$KIND" = lib ]; then
        g++ -shared -Wl,--exclude-libs,ALL -o "$TARGET.tmp" unity.o "$RT/libvlrt.a" -lpthread -ldl -lm
    else
        g++ -o "$TARGET.tmp" unity.o "$RT/libvlrt.a" "$LIB" -lpthread -ldl -lm
    fi
    mv "$TARGET.tmp" "$TARGET"
) > "$OUT/build.log" 2>&1 || { cat "$OUT/build.log" >&2; exit 2; }
