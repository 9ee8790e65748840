#!/usr/bin/env bash
# Generic yosys synthesis of the twin, for area bookkeeping (hdl/SYNTH.md).
#
#   hdl/scripts/synth.sh [SYNC_DEPTH] [CNT_W]      (defaults 2 16)
#
# Runs, from the repository root,
#   yosys -p 'read_verilog <hdl/pmu50.f>; chparam ...; synth -top pmu50; stat'             (hierarchical)
#   yosys -p 'read_verilog <hdl/pmu50.f>; chparam ...; synth -top pmu50 -flatten; stat'    (flat)
# and prints flip-flops and cells per block and in total. Logs: hdl/build/synth_<sd>_<w>_{hier,flat}.log
set -euo pipefail
HDL="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$HDL/.."
SD="${1:-2}"
W="${2:-16}"
mkdir -p "$HDL/build"
FILES=$(sed 's|^|hdl/|' "$HDL/pmu50.f" | tr '\n' ' ')
CH="chparam -set SYNC_DEPTH $SD -set CNT_W $W pmu50"
H="$HDL/build/synth_${SD}_${W}_hier.log"
L="$HDL/build/synth_${SD}_${W}_flat.log"
yosys -p "read_verilog $FILES; $CH; synth -top pmu50; stat" > "$H" 2>&1
yosys -p "read_verilog $FILES; $CH; synth -top pmu50 -flatten; stat" > "$L" 2>&1
# Last `stat` block of a log: "module cells dffs"
summarize() {
    awk '
        /^[0-9]+\. Printing statistics/ {blk++; delete cells; delete ff; n = 0}
        /^=== .* ===$/ {m = $2; if (m ~ /^\$paramod/) {split(m, p, "\\"); m = p[2]} mods[blk, ++n] = m; cur = m}
        /Number of cells:/ {cells[cur] = $4}
        /\$_.*DFF/ {ff[cur] += $2}
        END {for (i = 1; i <= n; i++) {m = mods[blk, i]; printf "%-32s %6d %6d\n", m, cells[m], ff[m]}}
    ' "$1"
}
echo "SYNC_DEPTH=$SD CNT_W=$W  (yosys $(yosys -V | awk '{print $2}'), generic gates, synth -top pmu50)"
printf '%-32s %6s %6s\n' "module (hierarchical)" cells flops
summarize "$H" | grep -v '^design'
printf '%-32s %6s %6s\n' "flattened (synth -flatten)" cells flops
summarize "$L"
echo "cell types (flattened):"
sed -n '/^[0-9]*\. Printing statistics/,$p' "$L" | awk '/\$_/ {printf "  %-16s %6d\n", $1, $2}' | sort -u -k1,1
