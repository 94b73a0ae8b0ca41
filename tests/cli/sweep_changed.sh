#!/bin/sh
# A sweep over a user's OS machine file, run twice with the file edited in between: the second run
# must run both cells again and name the machine as what changed.  Usage: sweep_changed.sh NESSHI DIR
set -e
nesshi=$1; dir=$2
rm -rf "$dir"; mkdir -p "$dir"
"$nesshi" isa --machine-toml os > "$dir/os.toml"
cat > "$dir/spec.toml" <<SPEC
metrics = ["cycles.total"]
[axes]
scene = "tetra:1"
size = 8
grid = 4
fifo_capacity = [0, 24]
os_machine = "$dir/os.toml"
SPEC
"$nesshi" sweep "$dir/spec.toml" --out "$dir/out" -q
sed -i 's/^branch_penalty = .*/branch_penalty = 2/' "$dir/os.toml"
"$nesshi" sweep "$dir/spec.toml" --out "$dir/out"
