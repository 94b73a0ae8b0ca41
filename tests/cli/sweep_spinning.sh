#!/bin/sh
# A sweep where one cell's OS kernel never ends (finding S2 of issue 24): that cell fails alone,
# past its cycle limit, and the sweep still writes the other cell's results and exits 1.
# Usage: sweep_spinning.sh NESSHI DIR
set -u
nesshi=$1; dir=$2
rm -rf "$dir"; mkdir -p "$dir"
cp -r kernels "$dir/spin"
rm -f "$dir/spin/os/dda.pk"
printf '# machine: os\nspin:   beqz r0, spin\n        halt\n' > "$dir/spin/os/dda.s"
cat > "$dir/spec.toml" <<SPEC
metrics = ["cycles.total"]
[axes]
scene = "tetra:1"
size = 4
grid = 4
kernels = ["$(pwd)/kernels", "$dir/spin"]
max_cycles = 200000
SPEC
"$nesshi" sweep "$dir/spec.toml" --out "$dir/out" -q > "$dir/log" 2>&1
status=$?
cat "$dir/log"
[ $status -eq 1 ] || { echo "FAIL: exit $status, want 1"; exit 1; }
grep -q "1 of 2 cell(s) failed" "$dir/log" || { echo "FAIL: no failed-cell count"; exit 1; }
grep -q "cycle limit (200000 cycles)" "$dir/log" || { echo "FAIL: the reason is not the cycle limit"; exit 1; }
[ "$(wc -l < "$dir/out/results.csv")" -eq 2 ] || { echo "FAIL: results.csv should hold the header and one cell"; exit 1; }
echo "ok: the spinning cell failed alone"
