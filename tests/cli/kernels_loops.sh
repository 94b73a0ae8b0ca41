#!/usr/bin/env bash
# `nesshi kernels --loops`: the pipeliner's report of each loop scheduled for the machines, with
# the .pk's own line numbers (the report's range starts at the region's `.pipeline`); on the
# presets, a line saying no kernel has loops. Usage: kernels_loops.sh NESSHI SOURCE_DIR
set -u
nesshi=$1; src=$2
export NESSHI_CACHE_DIR=
out=$("$nesshi" kernels --os-machine os-real --loops) || { echo "FAILED: exit $?"; exit 1; }
line=$(grep -n '^        \.pipeline' "$src/kernels/os/dda.pk" | head -1 | cut -d: -f1)
echo "$out" | grep -q "^os kernel: its loops as scheduled for os-real$" || { echo "FAILED: no os heading"; echo "$out" | tail -40; exit 1; }
echo "$out" | grep -q "^# SOFTWARE PIPELINE INFORMATION (kernels/os/dda.pk on os-real, lines $line-[0-9]*)$" ||
  { echo "FAILED: the report's lines are not the .pk's (its .pipeline is at line $line)"; echo "$out" | grep "SOFTWARE PIPELINE"; exit 1; }
echo "$out" | grep -q "^#   MaxLive: " || { echo "FAILED: not the whole report"; exit 1; }
"$nesshi" kernels --loops --json - 2>/dev/null | python3 -c 'import json,sys; j=json.load(sys.stdin); assert j["loop_reports"] == {}, j["loop_reports"]' ||
  { echo "FAILED: the presets' JSON has loop reports"; exit 1; }
"$nesshi" kernels --loops | grep -q "^no kernel has loops scheduled for its machine" || { echo "FAILED: presets"; exit 1; }
echo ok
