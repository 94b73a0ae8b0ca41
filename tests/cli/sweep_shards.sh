#!/bin/sh
# A sweep run as two shards whose cell folders are merged gives the same results as one run, and
# the merged run runs nothing; a shard writes no results of its own (they would look whole), and
# says how many cells it has.  Usage: sweep_shards.sh NESSHI SPEC DIR
set -e
nesshi=$1; spec=$2; dir=$3
rm -rf "$dir"; mkdir -p "$dir/merged/cells"
"$nesshi" sweep "$spec" --out "$dir/one" -q
"$nesshi" sweep "$spec" --out "$dir/s1" --shard 1/2 2>"$dir/s1.err"
grep -q "1 of the sweep's 2 cells in $dir/s1/cells (shard 1/2): no results until they all are" "$dir/s1.err"
test ! -e "$dir/s1/results.csv"
"$nesshi" sweep "$spec" --out "$dir/s2" --shard 2/2 -q
cp "$dir"/s1/cells/*.json "$dir"/s2/cells/*.json "$dir/merged/cells/"
"$nesshi" sweep "$spec" --out "$dir/merged"
cmp "$dir/one/results.csv" "$dir/merged/results.csv"
cmp "$dir/one/results.jsonl" "$dir/merged/results.jsonl"
echo "merged shards equal the single run"
