#!/usr/bin/env bash
# Method 1 (vector replay) with Icarus Verilog, for one vector file.
#
#   hdl/scripts/run_vectors.sh FILE.vec [--mutant MUT_NAME] [--vcd OUT.vcd] [--nocheck]
#
# Reads the `// param NAME VALUE` and `// clock_ns N` header lines, compiles hdl/tb/tb_vectors.v
# with `-P tb_vectors.NAME=VALUE` (cached per parameter set and mutant in hdl/build/iv/) and runs
# vvp. Exit 0 and `PASS ticks=<n>` on success; exit 1 with `MISMATCH tick=...` lines otherwise;
# exit 2 on bad input or a compile error.
set -uo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/common.sh"
VEC=""
MUT=none
VCD=""
NOCHECK=0
while [ $# -gt 0 ]; do
    case "$1" in
        --mutant) MUT="$2"; shift 2 ;;
        --vcd) VCD="$2"; shift 2 ;;
        --nocheck) NOCHECK=1; shift ;;
        -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
        *) if [ -z "$VEC" ]; then VEC="$1"; shift; else echo "run_vectors: unexpected argument $1" >&2; exit 2; fi ;;
    esac
done
[ -n "$VEC" ] && [ -r "$VEC" ] || { echo "run_vectors: cannot read vector file '$VEC'" >&2; exit 2; }

# Parameters from the header.
ARGS=()
vec_params "$VEC" -Ptb_vectors.
# 1 us timescale (as the model's VCD) when the half period is a whole number of microseconds.
if [ $(( CLOCK_NS % 2000 )) -ne 0 ]; then ARGS+=("-DTB_TIMESCALE_NS"); fi
[ "$MUT" != none ] && ARGS+=("-D$MUT")
# The twin's waveform freezes its internals at the last edge (for `pmu50 diff`); any other RTL
# is read on its ports only.
rtl_files
[ -n "$VCD" ] && [ "$FLIST" -ef "$HDL/pmu50.f" ] && ARGS+=("-DTB_TWIN_INTERNALS")

# An RTL other than the twin is instantiated with the parameters its top has (a netlist has
# none): `pmu50 rtl-info` reads them (and checks the port contract).
INST_DIR=""
if ! [ "$FLIST" -ef "$HDL/pmu50.f" ]; then
    INFO=$("$PMU50" rtl-info --rtl "$FLIST") || { echo "run_vectors: the RTL of $FLIST is refused" >&2; exit 2; }
    PARAMS=$(printf '%s\n' "$INFO" | sed -n '/"parameters": \[/,/\]/p' | grep -o '"[A-Z_0-9]*"' | tr -d '"' | tr '\n' ' ')
    INST_DIR="${PMU50_BUILD_DIR:-$HDL/build}/iv/inst_$(printf '%s' "$PARAMS" | md5sum | cut -c1-8)"
    mkdir -p "$INST_DIR"
    {
        P=""; for n in $PARAMS; do P="$P${P:+, }.$n($n)"; done
        C=""; for n in clk rst_n ig vs2_ok cmp_s cmp_c bus_we bus_addr bus_wdata sig vr_hi vm_en vs1_en vs2_en vp_en rail_hi st sr ps_win smp cs cc cnt_s cnt_c cnt_r si hist_s hist_c diag quadrant_skip bus_rdata bus_err; do C="$C${C:+, }.$n($n)"; done
        if [ -n "$P" ]; then echo "    pmu50 #($P) dut ($C);"; else echo "    pmu50 dut ($C);"; fi
    } > "$INST_DIR/tb_dut_inst.vh"
    ARGS+=("-DTB_DUT_INST" "-I$INST_DIR")
fi
KEY=$(printf '%s\n' "${ARGS[@]}" "${RTL[@]}" | md5sum | cut -c1-12)
DIR="${PMU50_BUILD_DIR:-$HDL/build}/iv/$MUT"
VVP="$DIR/$KEY.vvp"
mkdir -p "$DIR"
stale=0
[ -f "$VVP" ] || stale=1
if [ $stale = 0 ]; then
    for s in "$HDL/tb/tb_vectors.v" "${RTL[@]}"; do [ "$s" -nt "$VVP" ] && stale=1; done
fi
if [ $stale = 1 ]; then
    TMP="$VVP.$$.tmp"
    if ! iverilog -g2005 -Wall -Wno-timescale "${ARGS[@]}" -s tb_vectors -o "$TMP" \
            "$HDL/tb/tb_vectors.v" "${RTL[@]}" > "$TMP.log" 2>&1 || [ -s "$TMP.log" ]; then
        cat "$TMP.log" >&2
        rm -f "$TMP" "$TMP.log"
        echo "run_vectors: iverilog failed" >&2
        exit 2
    fi
    rm -f "$TMP.log"
    mv -f "$TMP" "$VVP"
fi

PLUS=("+vec=$VEC")
[ -n "$VCD" ] && PLUS+=("+vcd=$VCD")
[ $NOCHECK = 1 ] && PLUS+=("+nocheck")
OUT=$(vvp -n "$VVP" "${PLUS[@]}" 2>&1)
rc=$?
printf '%s\n' "$OUT" | grep -v '^VCD info:'
if grep -q '^MISMATCH' <<< "$OUT"; then exit 1; fi
if [ $rc -ne 0 ]; then exit 2; fi
if grep -q -E '^(PASS|DONE) ticks=' <<< "$OUT"; then exit 0; fi
exit 2
