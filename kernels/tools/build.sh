#!/bin/sh
# Regenerates the scheduled kernels from their sources: `nesshi schedule` bundles the
# straight-line blocks of each .pk file (and places their virtual registers).
#   kernels/tools/build.sh          rewrites the committed os/dda.s, seq/dda.s, ic/intersect.s and
#                                   seq/intersect.s in place
#   kernels/tools/build.sh OUTDIR   writes the same files under OUTDIR instead (the
#                                   kernels.regenerate CTest compares them)
# NESSHI names the nesshi binary (default: build/nesshi of this checkout).
# os/dda.s is the os preset's build of os/dda.pk: its `#if machine os` sections (the hand-scheduled
# voxel loop and its two leave paths) are kept and the `#else` ones (the `.pipeline while` region)
# dropped, so nothing here pipelines; other machines get the region modulo-scheduled for them when
# the kernel is built for them (kbuild::assemble_kernel), never from a file written here.
set -eu
kernels="$(cd "$(dirname "$0")/.." && pwd)"
nesshi="${NESSHI:-$kernels/../build/nesshi}"
if [ ! -x "$nesshi" ]; then
    echo "kernels/tools/build.sh: error: $nesshi not found; build first (make) or set NESSHI" >&2
    exit 1
fi
out="${1:-$kernels}"
mkdir -p "$out/os" "$out/seq" "$out/ic"

# `nesshi schedule -o` writes beside its target first, so a failing run leaves the old file whole.
sched() { # sched MACHINE SOURCE OUTPUT
    "$nesshi" schedule -m "$1" "$2" -I "$kernels/ic" -o "$3"
}
sched os "$kernels/os/dda.pk" "$out/os/dda.s"
sched seq "$kernels/seq/dda.pk" "$out/seq/dda.s"
sched ic "$kernels/ic/intersect.pk" "$out/ic/intersect.s"
sched seq "$kernels/seq/intersect.pk" "$out/seq/intersect.s"
