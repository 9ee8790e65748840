#!/usr/bin/env bash
# Figures of docs/cluster.md, measured without a scheduler on this machine:
#  - sharding overhead: the same N seeds as one process (--jobs 1) and as K shards
#    (--shard I/K --jobs 1) run one after another, wall time of each;
#  - merging M shard folders (pmu50 merge of M folders of a run of M*PER seeds).
#   cluster/bench_shards.sh [--seeds N] [--shards K] [--merge-folders M] [--per-folder PER] [--bin PMU50]
# (--merge-folders 0 skips the merge figure; defaults: 2000 seeds, 10 shards, 1000 folders of 10)
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/.." && pwd)
seeds=2000 shards=10 folders=1000 per=10 bin=$root/target/release/pmu50
while [ $# -gt 0 ]; do
  case "$1" in
    --seeds) seeds=$2; shift 2 ;;
    --shards) shards=$2; shift 2 ;;
    --merge-folders) folders=$2; shift 2 ;;
    --per-folder) per=$2; shift 2 ;;
    --bin) bin=$2; shift 2 ;;
    *) echo "bench_shards: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
[ -x "$bin" ] || { echo "bench_shards: no pmu50 binary at $bin" >&2; exit 2; }
tmp=$(mktemp -d "${TMPDIR:-/tmp}/pmu50-bench.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
now() { date +%s.%N; }
secs() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", b - a }'; }
quiet() { "$@" >/dev/null 2>&1; local rc=$?; [ $rc -le 1 ] || { echo "bench_shards: '$*' exit $rc" >&2; exit 1; }; }

echo "machine: $(nproc) CPUs, $(uname -r), pmu50 $("$bin" --version 2>/dev/null | awk '{print $2}')"
# Wall and CPU seconds (user + system) of a command: "WALL CPU". CPU time is the steadier figure
# on a shared machine; both are printed.
TIMEFORMAT='%R %U %S'
timed() { local t; t=$( { time quiet "$@"; } 2>&1 ) || exit 1; awk '{ printf "%.2f %.2f", $1, $2 + $3 }' <<<"$t"; }
read -r one_w one_c < <(timed "$bin" regress --start-seed 0 --iterations "$seeds" --jobs 1 --out "$tmp/one")
shards_all() {
  for i in $(seq 0 $((shards - 1))); do
    quiet env -u SLURM_ARRAY_TASK_ID -u JOB_COMPLETION_INDEX "$bin" regress --start-seed 0 --iterations "$seeds" --jobs 1 \
      --shard "$i/$shards" --out "$tmp/s/shard-$i"
  done
}
read -r k_w k_c < <(timed shards_all)
read -r m_w m_c < <(timed "$bin" merge --out "$tmp/merged" "$tmp"/s/shard-*)
[ -n "$one_w" ] && [ -n "$k_w" ] && [ -n "$m_w" ] || { echo "bench_shards: a run failed" >&2; exit 1; }
python3 "$here/compare.py" runs "$tmp/merged" "$tmp/one" >/dev/null || { echo "bench_shards: the $shards shards merged differ from one process" >&2; exit 1; }
awk -v n="$seeds" -v k="$shards" -v ow="$one_w" -v oc="$one_c" -v kw="$k_w" -v kc="$k_c" -v mw="$m_w" 'BEGIN {
  printf "sharding overhead: %d seeds (--jobs 1): one process %.2f s wall, %.2f s CPU (%.2f ms CPU/seed); %d shards one after another %.2f s wall (%+.1f %%), %.2f s CPU (%+.1f %%, %.0f ms CPU per shard); merge of the %d %.2f s; merged = one process\n",
    n, ow, oc, 1000 * oc / n, k, kw, 100 * (kw - ow) / ow, kc, 100 * (kc - oc) / oc, 1000 * (kc - oc) / k, k, mw }'

[ "$folders" -gt 0 ] || exit 0
total=$((folders * per))
t0=$(now)
for i in $(seq 0 $((folders - 1))); do
  quiet env -u SLURM_ARRAY_TASK_ID -u JOB_COMPLETION_INDEX "$bin" regress --start-seed 0 --iterations "$total" --jobs 1 \
    --shard "$i/$folders" --out "$tmp/m/shard-$i"
done
t1=$(now)
read -r mm_w mm_c < <(timed "$bin" merge --out "$tmp/m-merged" "$tmp"/m/shard-*)
[ -n "$mm_w" ] || { echo "bench_shards: the merge of $folders folders failed" >&2; exit 1; }
[ -s "$tmp/m-merged/missing.txt" ] && { echo "bench_shards: the $folders folders miss seeds" >&2; exit 1; }
echo "merge: $folders shard folders of $per seeds ($total seeds; written in $(secs "$t0" "$t1") s) merged in $mm_w s wall, $mm_c s CPU"
