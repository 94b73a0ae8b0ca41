#!/bin/bash
# A closed stderr never aborts (issue 28): `nesshi sweep SPEC --out D 2>&1 | head -2` once ended in
# SIGABRT (a progress line's EPIPE thrown in a worker thread) with no results written. Now the
# progress is dropped, every cell runs, the results are written and the exit status is 0; the
# same for a render writing its image.  Usage: closed_stderr.sh NESSHI SPEC DIR
set -u
nesshi=$1; spec=$2; dir=$3
rm -rf "$dir"; mkdir -p "$dir"
"$nesshi" sweep "$spec" --out "$dir/sweep" 2>&1 | head -2 > /dev/null
status=${PIPESTATUS[0]}
[ "$status" = 0 ] || { echo "sweep with a closed stderr: exit $status"; exit 1; }
rows=$(($(wc -l < "$dir/sweep/results.csv") - 1))
[ "$rows" = 24 ] || { echo "sweep with a closed stderr: $rows result rows, not 24"; exit 1; }
"$nesshi" render tetra:1 --size 8 --grid 4 --model V -o "$dir/t.png" 2>&1 | head -1 > /dev/null
status=${PIPESTATUS[0]}
[ "$status" = 0 ] && [ -s "$dir/t.png" ] || { echo "render with a closed stderr: exit $status"; exit 1; }
echo "ok: a closed stderr drops the progress, the work finishes"
