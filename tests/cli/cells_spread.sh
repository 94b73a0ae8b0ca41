#!/bin/sh
# Cells spread over shards or MPI processes give the same reports as one process running them all.
#   cells_spread.sh shards NESSHI DIR ARGS...   `paper`/`sweep` ARGS as two shards, merged, then once more
#   cells_spread.sh mpi NESSHI DIR ARGS...      the same ARGS under `mpirun -n 2`
# ARGS is the command and its arguments without --out (e.g. `sweep spec.toml`, `paper --size 8 ...`);
# every report file of the single run must be byte-identical in the spread run.
set -e
mode=$1; nesshi=$2; dir=$3; shift 3
rm -rf "$dir"; mkdir -p "$dir"
"$nesshi" "$@" --out "$dir/one" -q
case $mode in
shards)
    "$nesshi" "$@" --out "$dir/s1" --shard 1/2 > "$dir/s1.out" 2>&1
    "$nesshi" "$@" --out "$dir/s2" --shard 2/2 -q
    mkdir -p "$dir/spread/cells"
    # (a cell both shards hold, e.g. the pre-pass at the matrix's size, is the same run: either copy)
    cp "$dir"/s1/cells/*.json "$dir/spread/cells/"
    cp "$dir"/s2/cells/*.json "$dir/spread/cells/"
    # A paper shard writes no reports: they need every cell.
    if [ "$1" = paper ] && ! grep -q 'the reports wait for every cell' "$dir/s1.out"; then
        cat "$dir/s1.out"; echo "a paper shard did not say its reports wait"; exit 1
    fi
    "$nesshi" "$@" --out "$dir/spread" ;;
mpi)
    # OpenMPI refuses root unless told (CI containers run as root); never more ranks than cores matter here.
    OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 \
        mpirun -n 2 --oversubscribe "$nesshi" "$@" --out "$dir/spread" ;;
*) echo "cells_spread.sh: unknown mode '$mode'" >&2; exit 2 ;;
esac
n=0
for f in "$dir"/one/*; do
    [ -f "$f" ] || continue
    cmp "$f" "$dir/spread/$(basename "$f")"
    n=$((n + 1))
done
echo "$mode: $n report files equal the single run's"
