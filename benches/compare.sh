#!/usr/bin/env bash
# `make bench`: the Rust model and the Verilog twin side by side, same stimulus, one run, one table
# (benches/compare/main.rs prints it; docs/performance.md explains it).
#
#   benches/compare.sh [--seconds S]     (CPU seconds per untraced harness and stimulus, default 1)
#
# 1. target/release/pmu50 writes the stimuli as vector files: scenarios/keyoff_turns.toml and the
#    seeded random scenario PMU50_BENCH_SEED (default 7, as `pmu50 random --seed 7`);
# 2. hdl/bench/build.sh builds the Verilator harness per stimulus, without and with --trace (the
#    model's signals, and every variable: --trace-all) (verilator -O3, g++ -O3; cached in
#    hdl/build/bench/), benches/verilator_threads.sh the one of every variable with --threads 1
#    and 2, its loop timed by the wall clock (the wall-time table); iverilog compiles tb_vectors.v for the Icarus row (keyoff_turns only);
# 3. cargo bench --bench compare runs every harness and prints the table; exit 1 when the output
#    checksums of the harnesses differ;
# 4. cargo bench --bench regress_speed: what a regression seed costs (coverage and checks against
#    the bench and the kernel) and pmu50 regress's seeds per second on every core;
# 5. benches/build_modes.sh: a directed regression after a one-line RTL edit, cold cache, with
#    and without code coverage, against the goals of build modes (BUILD_MODES_SKIP=1 leaves it
#    out; BUILD_MODES_ARGS="--signoff --mutation" adds a cold make signoff and the mutation table);
# 6. benches/formal_time.py: make formal and make formal-quick cold, against their goals and
#    against ABC alone (FORMAL_SKIP=1 leaves this part out).
# Needs verilator and iverilog (installed with apt-get when missing, as `make deps` does).
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/../hdl/scripts/common.sh"
B="$ROOT/hdl/build/bench"
SEED="${PMU50_BENCH_SEED:-7}"
SECONDS_ARG=()
case "${1:-}" in
    --seconds) SECONDS_ARG=(--seconds "$2") ;;
    -h|--help) sed -n '2,18p' "$0"; exit 0 ;;
esac
mkdir -p "$B"
for t in verilator iverilog vvp g++; do
    command -v "$t" > /dev/null || { echo "compare: $t missing; installing verilator iverilog g++" >&2;
        (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends verilator iverilog g++) > "$B/apt.log" 2>&1 \
        || { echo "compare: apt-get failed, see $B/apt.log" >&2; exit 2; }; break; }
done
cd "$ROOT"
cargo build --release --bin pmu50 >&2
"$PMU50" vectors scenarios/keyoff_turns.toml -o "$B/keyoff_turns.vec" >&2
"$PMU50" random --seed "$SEED" -o "$B/random_$SEED.toml"
"$PMU50" vectors "$B/random_$SEED.toml" -o "$B/random_$SEED.vec" >&2
for s in keyoff_turns "random_$SEED"; do
    echo "compare: Verilator harnesses for $s (cached)" >&2
    "$ROOT/hdl/bench/build.sh" "$B/$s.vec" "$B/vl_$s"
    "$ROOT/hdl/bench/build.sh" "$B/$s.vec" "$B/vlt_$s" --trace
    "$ROOT/hdl/bench/build.sh" "$B/$s.vec" "$B/vla_$s" --trace-all
    "$ROOT/benches/verilator_threads.sh" "$B/$s.vec" "$B/vlw1_$s" 1
    "$ROOT/benches/verilator_threads.sh" "$B/$s.vec" "$B/vlw2_$s" 2
done
# Icarus: the vector-replay testbench of method 1, compiled with the file's parameters (as
# hdl/scripts/run_vectors.sh does).
ARGS=()
vec_params "$B/keyoff_turns.vec" -Ptb_vectors.
rtl_files "$HDL/pmu50.f"
iverilog -g2005 -Wall -Wno-timescale "${ARGS[@]}" -s tb_vectors -o "$B/iv_keyoff_turns.vvp" "$HDL/tb/tb_vectors.v" "${RTL[@]}"
cargo bench --bench compare -- --dir "$B" --stim keyoff_turns --stim "random_$SEED" --icarus keyoff_turns "${SECONDS_ARG[@]}"
cargo bench --bench regress_speed
# shellcheck disable=SC2086
[ "${BUILD_MODES_SKIP:-0}" = 1 ] || "$ROOT/benches/build_modes.sh" ${BUILD_MODES_ARGS:-}
[ "${FORMAL_SKIP:-0}" = 1 ] || python3 "$ROOT/benches/formal_time.py"
