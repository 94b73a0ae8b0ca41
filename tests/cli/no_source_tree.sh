#!/usr/bin/env bash
# no_source_tree.sh NESSHI WORKDIR: the machine runs from a copy of the binary, in a folder with no
# source tree beside it (the kernels are embedded), and the image equals the native renderer's.
set -eu
nesshi=$1 work=$2
rm -rf "$work" && mkdir -p "$work/bin" "$work/run"
cp "$nesshi" "$work/bin/nesshi"
cd "$work/run"
env -u NESSHI_KERNELS "$work/bin/nesshi" render tetra:1 --size 8 --grid 4 --model V -o v.png -q
"$work/bin/nesshi" render tetra:1 --size 8 --grid 4 --model native -o native.png -q
cmp v.png native.png
echo "model V ran from $work/bin with no kernels/ folder beside it"
