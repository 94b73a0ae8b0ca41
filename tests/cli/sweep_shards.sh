#!/bin/sh
# A sweep run as two shards whose cell folders are merged gives the same results as one run, and
# the merged run runs nothing.  Usage: sweep_shards.sh NESSHI SPEC DIR
set -e
nesshi=$1; spec=$2; dir=$3
rm -rf "$dir"; mkdir -p "$dir/merged/cells"
"$nesshi" sweep "$spec" --out "$dir/one" -q
"$nesshi" sweep "$spec" --out "$dir/s1" --shard 1/2 -q
"$nesshi" sweep "$spec" --out "$dir/s2" --shard 2/2 -q
cp "$dir"/s1/cells/*.json "$dir"/s2/cells/*.json "$dir/merged/cells/"
"$nesshi" sweep "$spec" --out "$dir/merged"
cmp "$dir/one/results.csv" "$dir/merged/results.csv"
cmp "$dir/one/results.jsonl" "$dir/merged/results.jsonl"
echo "merged shards equal the single run"
