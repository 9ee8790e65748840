#!/usr/bin/env bash
# An installed pmu50 works without the checkout it was built from (run by `make test-install`,
# part of `make test-long`):
#   1. a copy of the checkout (its tracked files) is installed with `cargo install --path COPY
#      --root PREFIX`, then the copy is deleted;
#   2. from another folder, the installed binary runs a scenario, exports its HDL kit, and runs
#      `pmu50 regress --dut verilator` on the twin it carries (unpacked into the cache folder) and
#      on the exported kit with its map; builds go to the user cache folder.
# Work files: target/install-test/. Exit 0 when all hold, 1 otherwise.
set -uo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
T="$ROOT/target/install-test"
fail() { echo "install_test: FAIL: $*" >&2; exit 1; }
rm -rf "$T/copy" "$T/prefix" "$T/elsewhere"; mkdir -p "$T/copy" "$T/elsewhere"
(cd "$ROOT" && git ls-files -z | xargs -0 tar -cf - | tar -xf - -C "$T/copy") || fail "cannot copy the checkout"
# the dependencies compiled once into target/install-test/target (kept between runs)
CARGO_TARGET_DIR="$T/target" cargo install --quiet --locked --path "$T/copy" --root "$T/prefix" || fail "cargo install failed"
rm -rf "$T/copy"
BIN="$T/prefix/bin/pmu50"
[ -x "$BIN" ] || fail "$BIN missing"
cd "$T/elsewhere"
export PMU50_CACHE_DIR="$T/cache"
unset PMU50_HDL_DIR
printf 'name = "short"\nduration = "40 ms"\n' > short.toml
"$BIN" run short.toml --out-dir out > run.log 2>&1 || { cat run.log; fail "pmu50 run"; }
[ -s out/short.vcd ] || fail "pmu50 run wrote no waveform"
"$BIN" hdl export kit > export.log 2>&1 || { cat export.log; fail "pmu50 hdl export"; }
[ -s kit/pmu50.f ] && [ -s kit/pmu50.core ] || fail "the exported kit has no twin"
"$BIN" regress --dut verilator --iterations 3 --out r_twin > twin.log 2>&1 || { cat twin.log; fail "regress on the carried twin"; }
ls "$PMU50_CACHE_DIR"/hdl-*/pmu50.f > /dev/null 2>&1 || fail "the carried twin was not unpacked into the cache folder"
"$BIN" regress --dut verilator --rtl kit/pmu50.f --map kit/pmu50.map.toml --iterations 3 --out r_kit > kit.log 2>&1 || { cat kit.log; fail "regress on the exported kit"; }
ls -d "$PMU50_CACHE_DIR"/verilator/* > /dev/null 2>&1 || fail "no build in the cache folder"
echo "install_test: ok (installed into $T/prefix, the checkout copy deleted; run, hdl export and regress --dut verilator from $T/elsewhere)"
