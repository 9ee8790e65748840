#!/usr/bin/env bash
# The Slurm path end to end on a real scheduler (part of make test): the configured cluster, or
# a single-node one brought up here by cluster/slurm/local_cluster.sh and shut down after.
#  1. a 3-task job array with task 1 cancelled while it runs (scancel JOB_1): tasks 0 and 2
#     finish, task 1 stops where it was and leaves its output;
#  2. a pmu50 regression of a few seeds in 3 shards (cluster/slurm/pmu50_regress.sbatch), one
#     task cancelled mid-run: its finished results stay, the merge names exactly its missing
#     seeds, a resubmission of that task alone (pmu50 regress --resume) completes the run, and
#     the merged run equals the one-process run (cluster/regress_slurm.sh --fault).
# Where no cluster can be run (not root, no packages), one line says why and it exits 0.
#   cluster/test_slurm.sh [PMU50_BIN]        exit 0 pass or skipped, 1 fail
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/.." && pwd)
bin=${1:-$root/target/release/pmu50}

if [ "${PMU50_TEST_SLURM_INSIDE:-}" != 1 ]; then
  [ -x "$bin" ] || { echo "test_slurm: FAIL: no pmu50 binary at $bin (cargo build --release --bin pmu50)"; exit 1; }
  start=$(date +%s)
  # Enough seeds that a shard runs about 1.5 s, so that a task can be cancelled mid-run:
  # timed here on 16 seeds; at least 600 (3 shards of 200 seeds: pmu50 regress appends its
  # results in batches (32 seeds now), and the cancel comes after the first batch).
  if [ -z "${PMU50_TEST_SEEDS:-}" ]; then
    cal=$(mktemp -d "${TMPDIR:-/tmp}/pmu50-cal.XXXXXX")
    t0=$(date +%s%N)
    env -u SLURM_ARRAY_TASK_ID -u JOB_COMPLETION_INDEX "$bin" regress --start-seed 0 --iterations 16 --jobs 1 --out "$cal/r" >/dev/null 2>&1
    t1=$(date +%s%N)
    rm -rf "$cal"
    PMU50_TEST_SEEDS=$(awk -v ns=$((t1 - t0)) 'BEGIN { ms = ns / 16e6; n = 3 * int(1500 / (ms > 0.01 ? ms : 0.01) + 1); print (n < 600 ? 600 : (n > 30000 ? 30000 : n)) }')
  fi
  export PMU50_TEST_SEEDS
  PMU50_TEST_SLURM_INSIDE=1 LOCAL_CLUSTER_SKIP_PREFIX="test_slurm: skipped: " \
    "$here/slurm/local_cluster.sh" -- "$0" "$bin"; rc=$?
  # 77: local_cluster.sh has said in one line why no cluster can run here.
  [ $rc = 77 ] && exit 0
  [ $rc = 0 ] && echo "test_slurm: ok ($(($(date +%s) - start)) s with the bring-up and shutdown)"
  [ $rc = 0 ] || echo "test_slurm: FAIL (exit $rc)"
  exit $rc
fi

# In the repository's target/ folder: on a configured cluster the tasks may run on other nodes,
# which see the repository (a shared home) more often than this node's /tmp.
mkdir -p "$root/target"
tmp=$(mktemp -d "$root/target/test-slurm.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
fail() { echo "test_slurm: FAIL: $*"; exit 1; }
part=()
[ -n "${PMU50_SLURM_PARTITION:-}" ] && part=(--partition "$PMU50_SLURM_PARTITION")

# 1. The scheduler: an array, one task cancelled while it runs.
job=$(sbatch --parsable "${part[@]}" --array=0-2 --output="$tmp/a-%a.out" \
  --wrap 'echo "start $SLURM_ARRAY_TASK_ID of $SLURM_ARRAY_TASK_COUNT"; [ "$SLURM_ARRAY_TASK_ID" = 1 ] && exec sleep 120; echo end') \
  || fail "sbatch failed"
job=${job%%;*}
for _ in $(seq 300); do
  [ "$(squeue -h -j "${job}_1" -o %T 2>/dev/null)" = RUNNING ] && grep -q start "$tmp/a-1.out" 2>/dev/null && break
  sleep 0.1
done
[ "$(squeue -h -j "${job}_1" -o %T 2>/dev/null)" = RUNNING ] || fail "array task ${job}_1 did not start within 30 s"
scancel "${job}_1" || fail "scancel ${job}_1 failed"
for _ in $(seq 300); do [ -n "$(squeue -h -j "$job" -o %i 2>/dev/null)" ] || break; sleep 0.1; done
[ -n "$(squeue -h -j "$job" -o %i 2>/dev/null)" ] && fail "array job $job still queued 30 s after the cancel"
for t in 0 2; do grep -qx end "$tmp/a-$t.out" 2>/dev/null || fail "task $t did not finish: $(cat "$tmp/a-$t.out" 2>&1)"; done
grep -qx "start 1 of 3" "$tmp/a-1.out" || fail "task 1 left no output: $(cat "$tmp/a-1.out" 2>&1)"
# (task 1's shell is replaced by its sleep: a cancel that kills the sleep before the shell
# cannot let the shell go on to `echo end`; the job leaving the queue within 30 s of the cancel,
# long before the sleep's 120 s, is what shows the cancel)
grep -qx end "$tmp/a-1.out" && fail "task 1 ran to its end despite scancel"
echo "test_slurm: array job $job: tasks 0 and 2 finished, task 1 cancelled while running (scancel ${job}_1)"

# 2. A sharded regression with a task cancelled and resumed, against the one-process run.
"$here/regress_slurm.sh" --seeds "$PMU50_TEST_SEEDS" --shards 3 --jobs 2 --fault --bin "$bin" --out "$tmp/regress" "${part[@]}" \
  || fail "sharded regression on Slurm (cluster/regress_slurm.sh --fault)"
