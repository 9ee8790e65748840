#!/usr/bin/env bash
# Co-simulation of the Verilog twin (hdl/pmu50.v) against the Rust reference model, with the
# three verification methods, then a mutation check of the methods themselves.
#
# Any RTL with the contract ports: PMU50_FILELIST=list.f (make cosim RTL=list.f), read on its
# ports (methods 1 and 2; method 3 compares the signals both waveforms have), plus what
# PMU50_MAP=map.toml names (method 2); no lint and no mutants (they are the twin's).
#
#   hdl/cosim.sh [--random N] [--jobs J] [--no-mutants] [--mutants A,B,..] [--keep] [--seed0 S]
#
#   --random N     seeded random scenarios (`pmu50 random --seed S..S+N-1`), default 200
#   --stress N     core-level stress vector files (hdl/ffi/examples/stress_vectors.rs), default 10
#   --seed0 S      first seed, default 1
#   --jobs J       parallel jobs, default: number of CPUs
#   --no-mutants   skip the mutation phase
#   --mutants L    only these mutants (comma-separated names of hdl/mutants.txt)
#   --keep         keep the waveforms of passing runs (hdl/build/cosim/iv/)
#   --dpi          also run the SystemVerilog DPI-C lockstep (tb_lockstep_dpi.sv, Verilator
#                  --binary) on the shipped scenarios with default parameters and on one mutant;
#                  each run writes its coverage.json to hdl/build/cosim/dpi_cov/
#
# Scenarios: scenarios/*.toml (shipped), hdl/scenarios/*.toml (HDL directed), the random ones,
# plus core-level stress vectors (random port stimuli the scenario format cannot express: bus
# reads of every address, writes while sig = 0, RO/unmapped writes, ig glitches; the generator
# writes the model's VCD too).
# For each scenario: `pmu50 vectors SCEN -o F.vec --vcd-dir D` (vectors and model VCD, one run),
#   method 1  Icarus vector replay      hdl/scripts/run_vectors.sh (hdl/tb/tb_vectors.v)
#   method 2  Verilator lockstep        pmu50 lockstep F.vec (the RTL built per parameter set,
#                                       stepped beside the model; the twin with its map
#                                       hdl/pmu50.map.toml: every register and internal too)
#   method 3  waveform diff             pmu50 diff MODEL.vcd ICARUS.vcd --map pmu50=tb_vectors.dut
# All must report zero mismatches. Mutation phase: for every mutant of hdl/mutants.txt and every
# method, the scenarios are tried shortest first until one catches the mutant; the table gives
# the catching scenario and the first divergent tick (edge number = time / clock period).
# Exit 0: every clean run passes and every mutant is caught by every method; 1 otherwise;
# 2: tool or setup failure. Work files: hdl/build/cosim/.
set -uo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/scripts/common.sh"
B="$HDL/build/cosim"
MAX_COSIM_TICKS=${MAX_COSIM_TICKS:-10000000}
SELF="$HDL/cosim.sh"
# the RTL under test: the twin (with its map), or PMU50_FILELIST (with PMU50_MAP, if any)
if [ -n "${PMU50_FILELIST:-}" ] && ! [ "$PMU50_FILELIST" -ef "$HDL/pmu50.f" ]; then
    TWIN=0
    LOCKSTEP_ARGS=(--rtl "$PMU50_FILELIST")
    [ -n "${PMU50_MAP:-}" ] && LOCKSTEP_ARGS+=(--map "$PMU50_MAP")
else
    TWIN=1
    unset PMU50_FILELIST
    LOCKSTEP_ARGS=(--map "$HDL/pmu50.map.toml")
fi

# ------------------------------------------------------------------------------------ helpers
log() { printf '%s\n' "$*" >&2; }

# meta NAME -> "ticks sync_depth cnt_w clock_ns scenario_name"
meta() { cat "$B/meta/$1"; }

# model VCD of NAME
model_vcd() {
    local n
    n=$(awk '{print $5}' "$B/meta/$1")
    echo "$B/model/$1/$n.vcd"
}

# first divergent tick from a `pmu50 diff` report: "value mismatches: N (first at T UNIT)"
diff_tick() { # REPORT CLOCK_NS
    local t u
    read -r t u < <(sed -n 's/.*value mismatches: [0-9]* (first at \([0-9]*\) \([a-z]*\).*/\1 \2/p' "$1" | head -1)
    [ -z "${t:-}" ] && { echo "?"; return; }
    case "$u" in
        s) t=$((t * 1000000000)) ;; ms) t=$((t * 1000000)) ;; us) t=$((t * 1000)) ;; ns) ;; *) echo "?"; return ;;
    esac
    echo $((t / $2))
}

# method 3 for one vector file (already replayed into IV_VCD): exit 0 equal, 1 differ, 2 error
vcd_diff() { # NAME IV_VCD REPORT
    "$PMU50" diff "$(model_vcd "$1")" "$2" --map pmu50=tb_vectors.dut --allow-unmatched --max 10 > "$3" 2>&1
    local rc=$?
    # every model signal must have a partner in the twin (unmatched twin signals are allowed);
    # another RTL is compared on the signals both waveforms have (its ports at least)
    if [ $rc -eq 0 ] && [ "$TWIN" = 1 ] && ! grep -q 'only in left: 0;' "$3"; then
        echo "cosim: model signals without a partner in the twin" >> "$3"
        rc=2
    fi
    return $rc
}

# ------------------------------------------------------------------------------------ workers
# __clean NAME: the three methods on the clean twin; writes $B/clean/NAME.res
if [ "${1:-}" = "__clean" ]; then
    NAME="$2"
    read -r TICKS SD W CLK _ < <(meta "$NAME")
    V="$B/vec/$NAME.vec"
    IV="$B/iv/$NAME.vcd"
    R="$B/clean/$NAME"
    "$HDL/scripts/run_vectors.sh" "$V" --vcd "$IV" > "$R.vectors.log" 2>&1
    rc1=$?
    "$PMU50" lockstep "$V" "${LOCKSTEP_ARGS[@]}" > "$R.lockstep.log" 2>&1
    rc2=$?
    if [ $rc1 -le 1 ]; then vcd_diff "$NAME" "$IV" "$R.vcddiff.log"; rc3=$?; else rc3=2; echo "no Icarus waveform" > "$R.vcddiff.log"; fi
    res() { case $1 in 0) echo PASS ;; 1) echo "FAIL@$2" ;; *) echo ERROR ;; esac; }
    t1=$(sed -n 's/^MISMATCH tick=\([0-9]*\).*/\1/p' "$R.vectors.log" | head -1)
    t2=$(sed -n 's/^MISMATCH tick=\([0-9]*\).*/\1/p' "$R.lockstep.log" | head -1)
    t3=$(diff_tick "$R.vcddiff.log" "$CLK")
    echo "$NAME $TICKS $(res $rc1 "$t1") $(res $rc2 "$t2") $(res $rc3 "$t3")" > "$R.res"
    [ $rc1 -eq 0 ] && [ $rc3 -eq 0 ] && [ "${KEEP:-0}" = 0 ] && rm -f "$IV"
    exit 0
fi

# __mutant MUT: each method over the scenarios until one catches MUT. The lockstep goes first
# (fastest): the scenario hdl/cosim_first.txt names for MUT first, if it is in the list, then the
# scenarios with the default SYNC_DEPTH/CNT_W (one Verilator build), then the rest, shortest
# first each (every other parameter set is a build of the mutant); the other two methods then try
# the lockstep's catching scenario first, then the rest shortest first. Every method still has to
# catch the mutant by itself; the order only decides how soon.
if [ "${1:-}" = "__mutant" ]; then
    MUT="$2"
    M="$B/mut/$MUT"
    mkdir -p "$M"
    : > "$M.res"
    first=""
    for method in lockstep vectors vcddiff; do
        found="MISSED"
        if [ $method = lockstep ]; then
            hint=$(awk -v m="$MUT" '$1 == m {print $2}' "$HDL/cosim_first.txt" 2>/dev/null)
            grep -Fqx "${hint:-@none@}" "$B/order.txt" || hint=""
            order=$( ([ -n "$hint" ] && echo "$hint"
                      grep -Fx -f "$B/default_structural.txt" "$B/order.txt" | grep -Fvx "${hint:-@none@}"
                      grep -Fvx -f "$B/default_structural.txt" "$B/order.txt" | grep -Fvx "${hint:-@none@}") )
        else
            order=$( ([ -n "$first" ] && echo "$first"; grep -Fvx "${first:-@none@}" "$B/order.txt") )
        fi
        while read -r NAME; do
            [ -z "$NAME" ] && continue
            read -r TICKS SD W CLK _ < <(meta "$NAME")
            V="$B/vec/$NAME.vec"
            L="$M/$method.$NAME.log"
            case $method in
                vectors)
                    "$HDL/scripts/run_vectors.sh" "$V" --mutant "$MUT" > "$L" 2>&1
                    rc=$?
                    tick=$(sed -n 's/^MISMATCH tick=\([0-9]*\).*/\1/p' "$L" | head -1) ;;
                lockstep)
                    "$PMU50" lockstep "$V" "${LOCKSTEP_ARGS[@]}" --define "$MUT" > "$L" 2>&1
                    rc=$?
                    tick=$(sed -n 's/^MISMATCH tick=\([0-9]*\).*/\1/p' "$L" | head -1) ;;
                vcddiff)
                    IV="$M/$NAME.vcd"
                    "$HDL/scripts/run_vectors.sh" "$V" --mutant "$MUT" --nocheck --vcd "$IV" > "$L.sim" 2>&1
                    rc=$?
                    if [ $rc -eq 0 ]; then vcd_diff "$NAME" "$IV" "$L"; rc=$?; else cat "$L.sim" > "$L"; rc=2; fi
                    rm -f "$IV" "$L.sim"
                    tick=$(diff_tick "$L" "$CLK") ;;
            esac
            if [ $rc -eq 1 ]; then
                found="$NAME@$tick"
                [ $method = lockstep ] && first="$NAME"
                break
            fi
            if [ $rc -ge 2 ]; then found="ERROR($NAME)"; break; fi
            rm -f "$L"
        done <<< "$order"
        echo "$MUT $method $found" >> "$M.res"
    done
    exit 0
fi

# ------------------------------------------------------------------------------------ main
NRANDOM=200
NSTRESS=10
SEED0=1
JOBS=$(nproc 2>/dev/null || echo 2)
MUTANTS_ON=1
ONLY=""
KEEP=0
DPI=0
while [ $# -gt 0 ]; do
    case "$1" in
        --random) NRANDOM="$2"; shift 2 ;;
        --seed0) SEED0="$2"; shift 2 ;;
        --stress) NSTRESS="$2"; shift 2 ;;
        --jobs) JOBS="$2"; shift 2 ;;
        --no-mutants) MUTANTS_ON=0; shift ;;
        --mutants) ONLY="$2"; shift 2 ;;
        --keep) KEEP=1; shift ;;
        --dpi) DPI=1; shift ;;
        -h|--help) sed -n '2,30p' "$SELF"; exit 0 ;;
        *) log "cosim: unknown option $1 (see --help)"; exit 2 ;;
    esac
done
export KEEP
START=$(date +%s)
stamp() { echo "[$(( $(date +%s) - START ))s] $*" >&2; }

# Tools.
# hdl/build/ is git-ignored: a fresh clone does not have it.
mkdir -p "$HDL/build" "$B"
missing=0
for t in iverilog vvp verilator yosys; do command -v "$t" > /dev/null || missing=1; done
if [ $missing = 1 ]; then
    stamp "installing iverilog verilator yosys (apt-get)"
    (apt-get update && apt-get install -y iverilog verilator yosys) > "$HDL/build/apt.log" 2>&1 \
        || { log "cosim: apt-get failed, see hdl/build/apt.log"; exit 2; }
fi

stamp "cargo build --release (pmu50, pmu50-ffi, stress_vectors)"
# one command, the packages together: alone, pmu50-ffi resolves other features of serde than the
# workspace's tests do, and would compile serde and everything above it again
(cd "$ROOT" && cargo build --release -p pmu50 -p pmu50-ffi --examples) > /dev/null 2>&1 \
    || { (cd "$ROOT" && cargo build --release -p pmu50 -p pmu50-ffi --examples); log "cosim: cargo build failed"; exit 2; }

stamp "C ABI smoke test (hdl/ffi/tests/smoke.c)"
if ! cc -std=c99 -Wall -Wextra -pedantic -Werror -I "$HDL/ffi/include" "$HDL/ffi/tests/smoke.c" \
        "$PMU50_FFI_LIB" -lpthread -ldl -lm -o "$HDL/build/smoke" > "$HDL/build/smoke.log" 2>&1 \
        || ! "$HDL/build/smoke" >> "$HDL/build/smoke.log" 2>&1; then
    cat "$HDL/build/smoke.log"; log "cosim: C ABI smoke test failed"; exit 1
fi

stamp "lint: verilator --lint-only -Wall"
rtl_files "$HDL/pmu50.f"
if [ "$TWIN" = 0 ]; then
    log "cosim: the RTL of $PMU50_FILELIST: no lint and no mutants (they are the twin's)"
    MUTANTS_ON=0
elif ! verilator --lint-only -Wall --default-language 1364-2005 --top-module pmu50 "${RTL[@]}" > "$HDL/build/lint.log" 2>&1 \
        || [ -s "$HDL/build/lint.log" ]; then
    cat "$HDL/build/lint.log"; log "cosim: lint failed"; exit 1
fi

rm -rf "$B"
mkdir -p "$B"/{scen,vec,model,meta,clean,iv,mut}

# Scenario list: NAME PATH
{
    for f in "$ROOT"/scenarios/*.toml "$HDL"/scenarios/*.toml; do
        [ -e "$f" ] || continue
        # Days of parking (park_30d: 2.6e11 ticks) have no per-tick vector file or VCD: they are
        # compared with per-tick stepping by tests/skip_ahead.rs instead.
        ticks=$("$PMU50" check "$f" | sed -n 's/.*, \([0-9]*\) ticks)$/\1/p')
        if [ -n "$ticks" ] && [ "$ticks" -gt "$MAX_COSIM_TICKS" ]; then
            log "cosim: $(basename "$f") left out: $ticks ticks is more than MAX_COSIM_TICKS=$MAX_COSIM_TICKS"
            continue
        fi
        echo "$(basename "$f" .toml) $f"
    done
} > "$B/list.txt"
stamp "generating $NRANDOM random scenarios (seeds $SEED0..$((SEED0 + NRANDOM - 1)))"
for ((s = SEED0; s < SEED0 + NRANDOM; s++)); do
    "$PMU50" random --seed "$s" -o "$B/scen/random_$s.toml" || { log "cosim: pmu50 random failed"; exit 2; }
    echo "random_$s $B/scen/random_$s.toml" >> "$B/list.txt"
done
for ((s = 1; s <= NSTRESS; s++)); do echo "stress_$s @stress:$s" >> "$B/list.txt"; done
NSCEN=$(wc -l < "$B/list.txt")

stamp "vectors and model waveforms for $NSCEN scenarios ($NSTRESS stress)"
gen() { # NAME PATH|@stress:SEED
    mkdir -p "$B/model/$1"
    if [ "${2#@stress:}" != "$2" ]; then
        if ! "$STRESS" --seed "${2#@stress:}" -o "$B/vec/$1.vec" --vcd "$B/model/$1/$1.vcd" > "$B/vec/$1.log" 2>&1; then
            echo "stress vectors FAILED for $1:"; cat "$B/vec/$1.log"; return 1
        fi
    elif ! "$PMU50" vectors "$2" -o "$B/vec/$1.vec" --vcd-dir "$B/model/$1" > "$B/vec/$1.log" 2>&1; then
        echo "vectors FAILED for $2:"; cat "$B/vec/$1.log"; return 1
    fi
    awk -v n="$1" '
        /^\/\/ param SYNC_DEPTH/ {sd=$4} /^\/\/ param CNT_W/ {w=$4} /^\/\/ clock_ns/ {c=$3}
        /^\/\/ ticks/ {t=$3} /^\/\/ scenario/ {s=$3} /^[^\/]/ {exit}
        END {if (c == "") c = 10000; print t, sd, w, c, s}' "$B/vec/$1.vec" > "$B/meta/$1"
}
export -f gen
STRESS="$ROOT/target/release/examples/stress_vectors"
export B PMU50 STRESS
if ! xargs -P "$JOBS" -L 1 bash -c 'gen "$0" "$1"' < "$B/list.txt"; then
    log "cosim: vector generation failed"; exit 2
fi
# mutation order: shortest first
while read -r n _; do echo "$(awk '{print $1}' "$B/meta/$n") $n"; done < "$B/list.txt" \
    | sort -n -k1,1 -k2,2 | awk '{print $2}' > "$B/order.txt"
while read -r n; do
    [ "$(awk '{print $2, $3}' "$B/meta/$n")" = "2 16" ] && echo "$n"
done < "$B/order.txt" > "$B/default_structural.txt"

stamp "Verilator build of the RTL (checked against the port contract; one build per parameter set, cached)"
export TWIN
"$PMU50" rtl-info --rtl "${PMU50_FILELIST:-$HDL/pmu50.f}" > "$B/rtl_info.json" || { log "cosim: the RTL is refused"; exit 2; }

stamp "clean runs: $NSCEN scenarios x 3 methods"
awk '{print $1}' "$B/list.txt" | xargs -P "$JOBS" -n 1 "$SELF" __clean

# ------------------------------------------------------------------------------------ report
CLEAN_FAIL=0
{
    printf '\nClean runs (twin without mutants): %d scenarios\n' "$NSCEN"
    printf '  %-22s %8s  %-14s %-14s %-14s\n' scenario ticks vectors lockstep vcddiff
    npass=0
    while read -r n _; do
        if [ ! -f "$B/clean/$n.res" ]; then
            printf '  %-22s %8s  %s\n' "$n" "?" "NO RESULT"; CLEAN_FAIL=1; continue
        fi
        read -r _ t r1 r2 r3 < "$B/clean/$n.res"
        if [ "$r1 $r2 $r3" = "PASS PASS PASS" ]; then
            npass=$((npass + 1))
            case "$n" in random_*|stress_*) continue ;; esac   # list shipped/directed ones, failures only for generated
        else
            CLEAN_FAIL=1
        fi
        printf '  %-22s %8s  %-14s %-14s %-14s\n' "$n" "$t" "$r1" "$r2" "$r3"
    done < "$B/list.txt"
    nrand_pass=$(cat "$B"/clean/random_*.res 2>/dev/null | awk '$3=="PASS" && $4=="PASS" && $5=="PASS"' | wc -l)
    ticks_total=$(cat "$B"/meta/* | awk '{s += $1} END {print s}')
    nstress_pass=$(cat "$B"/clean/stress_*.res 2>/dev/null | awk '$3=="PASS" && $4=="PASS" && $5=="PASS"' | wc -l)
    printf '  random: %d of %d pass all three methods\n' "$nrand_pass" "$NRANDOM"
    printf '  stress: %d of %d pass all three methods\n' "$nstress_pass" "$NSTRESS"
    printf '  total: %d of %d scenarios pass all three methods (%d ticks each method)\n' "$npass" "$NSCEN" "$ticks_total"
} | tee "$B/report.txt"
n_clean_ok=$(cat "$B"/clean/*.res 2>/dev/null | awk '$3=="PASS" && $4=="PASS" && $5=="PASS"' | wc -l)
[ "$n_clean_ok" -eq "$NSCEN" ] || CLEAN_FAIL=1
if [ $CLEAN_FAIL = 1 ]; then
    echo "  failure logs: $B/clean/<scenario>.{vectors,lockstep,vcddiff}.log" | tee -a "$B/report.txt"
fi

MUT_FAIL=0
if [ $MUTANTS_ON = 1 ]; then
    # the mutants without a scope (a `regress` or `equivalent` one is for `make mutation` only)
    mapfile -t ALLMUT < <(grep -v '^#' "$HDL/mutants.txt" | awk -F'|' 'NF == 3 {gsub(/ /, "", $1); print $1}')
    if [ -n "$ONLY" ]; then IFS=',' read -r -a MUTS <<< "$ONLY"; else MUTS=("${ALLMUT[@]}"); fi
    stamp "mutation phase: ${#MUTS[@]} mutants x 3 methods"
    printf '%s\n' "${MUTS[@]}" | xargs -P "$JOBS" -n 1 "$SELF" __mutant
    {
        printf '\nMutation check: first catching scenario @ first divergent tick (scenarios tried shortest first)\n'
        printf '  %-30s %-26s %-26s %-26s\n' mutant "vectors (Icarus)" "lockstep (Verilator)" "vcddiff (pmu50 diff)"
        for m in "${MUTS[@]}"; do
            r1=$(awk -v m="$m" '$1==m && $2=="vectors" {print $3}' "$B/mut/$m.res" 2>/dev/null)
            r2=$(awk -v m="$m" '$1==m && $2=="lockstep" {print $3}' "$B/mut/$m.res" 2>/dev/null)
            r3=$(awk -v m="$m" '$1==m && $2=="vcddiff" {print $3}' "$B/mut/$m.res" 2>/dev/null)
            printf '  %-30s %-26s %-26s %-26s\n' "$m" "${r1:-NONE}" "${r2:-NONE}" "${r3:-NONE}"
        done
        caught=$(cat "$B"/mut/*.res 2>/dev/null | awk '$3 !~ /^(MISSED|ERROR)/' | wc -l)
        printf '  caught: %d of %d (mutant, method) pairs; logs: %s/mut/<mutant>/\n' "$caught" $(( ${#MUTS[@]} * 3 )) "$B"
        # the lockstep's catcher against hdl/cosim_first.txt: a stale or missing line only costs time
        for m in "${MUTS[@]}"; do
            got=$(awk -v m="$m" '$1==m && $2=="lockstep" {print $3}' "$B/mut/$m.res" 2>/dev/null | cut -d@ -f1)
            want=$(awk -v m="$m" '$1 == m {print $2}' "$HDL/cosim_first.txt" 2>/dev/null)
            case "$got" in ""|MISSED|ERROR*) continue ;; esac
            [ "$got" = "$want" ] || printf '  hdl/cosim_first.txt: %s is caught first by %s, the file says %s (update it to save the search)\n' "$m" "$got" "${want:-nothing}"
        done
    } | tee -a "$B/report.txt"
    for m in "${MUTS[@]}"; do
        n_ok=$(awk '$3 !~ /^(MISSED|ERROR)/' "$B/mut/$m.res" 2>/dev/null | wc -l)
        [ "$n_ok" -eq 3 ] || MUT_FAIL=1
    done
fi

DPI_FAIL=0
if [ $DPI = 1 ]; then
    stamp "SystemVerilog DPI-C lockstep (Verilator --binary)"
    {
        printf '\nSystemVerilog DPI-C lockstep (hdl/tb/lockstep/tb_lockstep_dpi.sv)\n'
        mkdir -p "$B/dpi_cov"
        for n in $(cat "$B/default_structural.txt"); do
            case "$n" in random_*) continue ;; esac
            grep -q '^// param ADAPTIVE 1$' "$B/vec/$n.vec" || continue
            "$HDL/scripts/run_lockstep_dpi.sh" "$B/vec/$n.vec" --coverage "$B/dpi_cov/$n.coverage.json" --run-id "dpi/$n" > "$B/clean/$n.dpi.log" 2>&1
            case $? in 0) r=PASS ;; 1) r="FAIL@$(sed -n 's/^MISMATCH tick=\([0-9]*\).*/\1/p' "$B/clean/$n.dpi.log" | head -1)" ;; *) r=ERROR ;; esac
            # the bench samples the coverage model through the C ABI and writes coverage.json
            [ -s "$B/dpi_cov/$n.coverage.json" ] || r="ERROR(no coverage.json)"
            printf '  %-22s %s\n' "$n" "$r"
            echo "$r" >> "$B/dpi.res"
        done
        "$HDL/scripts/run_lockstep_dpi.sh" "$B/vec/fig15b.vec" --mutant MUT_CTH_OFF_BY_ONE > "$B/mut/dpi.MUT_CTH_OFF_BY_ONE.log" 2>&1
        rc=$?
        t=$(sed -n 's/^MISMATCH tick=\([0-9]*\).*/\1/p' "$B/mut/dpi.MUT_CTH_OFF_BY_ONE.log" | head -1)
        if [ $rc = 1 ]; then printf '  MUT_CTH_OFF_BY_ONE on fig15b: caught @%s\n' "$t"; else printf '  MUT_CTH_OFF_BY_ONE on fig15b: MISSED\n'; echo MISSED >> "$B/dpi.res"; fi
        printf '  coverage.json of each run (sampled through the C ABI): %s/dpi_cov/\n' "$B"
    } | tee -a "$B/report.txt"
    grep -qv '^PASS$' "$B/dpi.res" 2>/dev/null && DPI_FAIL=1
fi

stamp "done"
if [ $DPI_FAIL = 1 ]; then echo "COSIM FAIL: DPI-C lockstep" | tee -a "$B/report.txt"; exit 1; fi
if [ $CLEAN_FAIL = 1 ]; then echo "COSIM FAIL: a clean run mismatched" | tee -a "$B/report.txt"; exit 1; fi
if [ $MUT_FAIL = 1 ]; then echo "COSIM FAIL: a mutant escaped a method" | tee -a "$B/report.txt"; exit 1; fi
echo "COSIM PASS" | tee -a "$B/report.txt"
exit 0
