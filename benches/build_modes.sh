#!/usr/bin/env bash
# `make bench`, build modes: what an HDL engineer's loop costs after a one-line RTL edit, cold
# cache (an empty PMU50_CACHE_DIR: the Verilator runtime is built too), beside the figures
# measured before build modes (one build per seed).
#
#   benches/build_modes.sh [--seeds N] [--signoff] [--mutation]
#
# Rows: N (400) directed seeds of an edited copy of the twin with its map; the same with
# --code-coverage (each beside its goal: met or missed); the same again after a second one-line
# edit with the cache of the first run (the builds are new, as the RTL's hash changed, but the
# edit is a comment, so the compiler cache serves the objects when ccache is installed); the
# seeds until every reachable bin was hit; the builds (first parameter set against the later
# ones, and the median of each step, from the cache's builds.log). --signoff adds a cold `make
# signoff`, --mutation the mutation table (median and most seeds to catch). Wall and CPU seconds
# of the whole command (children included), and the machine's load average when it started.
# A cold cache is an empty PMU50_CACHE_DIR, the compiler cache in it (CCACHE_DIR is unset).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SEEDS=400
SIGNOFF=0
MUTATION=0
while [ $# -gt 0 ]; do
    case "$1" in
        --seeds) SEEDS="$2"; shift ;;
        --signoff) SIGNOFF=1 ;;
        --mutation) MUTATION=1 ;;
        -h|--help) sed -n '2,12p' "$0"; exit 0 ;;
        *) echo "build_modes: unknown option $1" >&2; exit 2 ;;
    esac
    shift
done
cd "$ROOT"
unset CCACHE_DIR
cargo build --release --bin pmu50 >&2
PMU50="$ROOT/target/release/pmu50"
W="$ROOT/target/bench-build-modes"
rm -rf "$W"
mkdir -p "$W/rtl/rtl"
# the one-line edit: a copy of the twin whose top has one more line (a new content hash)
while read -r f; do
    case "$f" in *.v) cp "$ROOT/hdl/$f" "$W/rtl/$f" ;; esac
done < "$ROOT/hdl/pmu50.f"
cp "$ROOT/hdl/pmu50.f" "$W/rtl/pmu50.f"
echo "// edited $(date +%s)" >> "$W/rtl/pmu50.v"

row() { # name, command...: time one command with an empty cache; prints "wall cpu load"
    local name="$1"; shift
    local cache="$W/cache-$name"
    rm -rf "$cache"
    rerow "$name" "$cache" "$@"
}
rerow() { # name, cache, command...: the same with this cache as it is
    local name="$1" cache="$2"; shift 2
    PMU50_CACHE_DIR="$cache" python3 - "$W/$name.log" "$@" <<'PY'
import os, resource, subprocess, sys, time
load = os.getloadavg()[0]
t0 = time.monotonic()
with open(sys.argv[1], "w") as log:
    subprocess.run(sys.argv[2:], stdout=log, stderr=subprocess.STDOUT)
wall = time.monotonic() - t0
r = resource.getrusage(resource.RUSAGE_CHILDREN)
print(f"{wall:.1f} {r.ru_utime + r.ru_stime:.1f} {load:.1f}")
PY
}
REGRESS=("$PMU50" regress --directed --iterations "$SEEDS" --dut verilator --rtl "$W/rtl/pmu50.f"
    --map "$ROOT/hdl/pmu50.map.toml" --jobs 2 --no-triage)
R1=$(row plain "${REGRESS[@]}" --out "$W/plain")
R2=$(row code "${REGRESS[@]}" --code-coverage --out "$W/code")
# a second one-line edit, the caches of the first runs kept
echo "// edited again $(date +%s)" >> "$W/rtl/pmu50.v"
R3=$(rerow plain-again "$W/cache-plain" "${REGRESS[@]}" --out "$W/plain-again")
R4=$(rerow code-again "$W/cache-code" "${REGRESS[@]}" --code-coverage --out "$W/code-again")
OBJCACHE_NOW=$(command -v ccache >/dev/null && echo "ccache" || echo "no ccache")
python3 - "$W" "$SEEDS" "$R1" "$R2" "$R3" "$R4" "$OBJCACHE_NOW" "$(nproc)" <<'EOF'
import json, sys, glob, os, statistics
w, seeds, r1, r2 = sys.argv[1], int(sys.argv[2]), sys.argv[3].split(), sys.argv[4].split()
r3, r4, objcache, cores = sys.argv[5].split(), sys.argv[6].split(), sys.argv[7], sys.argv[8]
def closure(d):
    c = json.load(open(os.path.join(d, "coverage.json")))
    reach = {i for i, b in enumerate(c["bins"]) if not b.get("unreachable")}
    hit, n = set(), None
    for k, line in enumerate(open(os.path.join(d, "results.jsonl"))):
        cov = json.loads(line)["cov"]
        for kv in filter(None, cov.split(",")):
            hit.add(int(kv.split(":")[0]))
        if n is None and reach <= hit:
            n = k + 1
    return n, len(reach & hit), len(reach)
def builds(name):
    # "<key> <total> s [runtime R verilator V g++ G link L (ccache)]", in the order built
    # per edit (an RTL folder each), the first edit first
    logs = sorted(glob.glob(os.path.join(w, "cache-" + name, "verilator", "*", "builds.log")), key=os.path.getmtime)
    out = []
    for log in logs:
        rows = []
        for l in open(log):
            f = l.split()
            steps = {f[i]: float(f[i + 1]) for i in range(3, len(f) - 1, 2) if f[i] in ("runtime", "verilator", "g++", "link")}
            rows.append((float(f[1]), steps))
        out.append(rows)
    return out
def verdict(r, goal):
    return f"{'met' if float(r[0]) <= goal else 'missed'} (wall)"
print(f"\nBuild modes: {seeds} directed seeds of the twin after a one-line edit, cold cache, 2 jobs, {cores} cores, {objcache}")
print(f"{'what':<44} {'wall s':>8} {'CPU s':>8} {'load':>6}  {'goal':>8}  {'':<13} before build modes")
print(f"{'directed regression (--map)':<44} {r1[0]:>8} {r1[1]:>8} {r1[2]:>6}  {'<= 30':>8}  {verdict(r1, 30):<13} 219-284 s wall")
print(f"{'the same with --code-coverage':<44} {r2[0]:>8} {r2[1]:>8} {r2[2]:>6}  {'<= 60':>8}  {verdict(r2, 60):<13} (18.5 min for 200 seeds of an SV RTL)")
print(f"{'after a second edit, cache warm (--map)':<44} {r3[0]:>8} {r3[1]:>8} {r3[2]:>6}")
print(f"{'after a second edit, cache warm (coverage)':<44} {r4[0]:>8} {r4[1]:>8} {r4[2]:>6}")
for name, d in (("plain", "plain"), ("code", "code")):
    n, hit, total = closure(os.path.join(w, d))
    print(f"{'closure (' + name + ')':<44} {hit}/{total} reachable bins, all hit at seed {n}")
    edits = builds(name)
    if edits:
        cold = edits[0]
        first, rest = cold[0], cold[1:] or cold
        med = lambda k, rows: statistics.median(r[1].get(k, 0.0) for r in rows)
        print(f"{'builds (' + name + ')':<44} {len(cold)} libraries; the first {first[0]:.1f} s (runtime {first[1].get('runtime', 0):.1f} s), the others median {statistics.median(r[0] for r in rest):.1f} s: verilator {med('verilator', rest):.1f}, g++ {med('g++', rest):.1f}, link {med('link', rest):.1f}")
        again = [r for e in edits[1:] for r in e]
        if again:
            print(f"{'builds after the second edit (' + name + ')':<44} {len(again)} libraries, median {statistics.median(r[0] for r in again):.1f} s: g++ {med('g++', again):.1f}")
EOF
if [ "$SIGNOFF" = 1 ]; then
    rm -rf "$ROOT/hdl/build/formal/cache"
    R3=$(row signoff make -C "$ROOT" signoff FORMAL_CACHE=0)
    read -r wall cpu load <<< "$R3"
    printf "%-44s %8s %8s %6s  %8s  about 47 min\n" "cold make signoff" "$wall" "$cpu" "$load" "<= 600"
fi
if [ "$MUTATION" = 1 ]; then
    for mode in map ports; do
        extra=(); [ "$mode" = ports ] && extra=(--ports-only)
        R4=$(row "mutation-$mode" env PMU50_HDL_DIR="$ROOT/hdl" "$PMU50" mutation --iterations "$SEEDS" "${extra[@]}" --out "$W/mutation-$mode")
        read -r wall cpu load <<< "$R4"
        printf "%-44s %8s %8s %6s  %s\n" "make mutation ($mode)" "$wall" "$cpu" "$load" \
            "$(grep -E '^compared|^mutation score' "$W/mutation-$mode.log" | tr '\n' ' ') (before: median 4, most 139)"
    done
fi
