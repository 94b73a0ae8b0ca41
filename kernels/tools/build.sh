#!/bin/sh
# Regenerates the scheduled kernels from their sources: `nesshi schedule` bundles the
# straight-line blocks of each .pk file; gen_ic.py (python3) prints the IC kernel's .pk first.
#   kernels/tools/build.sh          rewrites the committed os/dda.s, seq/dda.s, ic/intersect.s and
#                                   seq/intersect.s in place; the generated ic/intersect.pk (the
#                                   IC kernel before scheduling) goes to a temporary directory
#   kernels/tools/build.sh OUTDIR   writes the same files, and ic/intersect.pk, under OUTDIR
#                                   instead (the kernels.regenerate CTest compares them)
# NESSHI names the nesshi binary (default: build/nesshi of this checkout).
set -eu
kernels="$(cd "$(dirname "$0")/.." && pwd)"
tools="$kernels/tools"
nesshi="${NESSHI:-$kernels/../build/nesshi}"
if ! command -v python3 >/dev/null 2>&1; then
    echo "kernels/tools/build.sh: error: python3 not found; the IC kernel's generator needs it" \
         "(scripts/install-deps.sh installs it)" >&2
    exit 1
fi
if [ ! -x "$nesshi" ]; then
    echo "kernels/tools/build.sh: error: $nesshi not found; build first (make) or set NESSHI" >&2
    exit 1
fi
if [ $# -gt 0 ]; then
    out="$1"
    work="$1"
else
    out="$kernels"
    work="$(mktemp -d)"
    trap 'rm -rf "$work"' EXIT
fi
mkdir -p "$out/os" "$out/seq" "$out/ic" "$work/ic"

# `nesshi schedule -o` writes beside its target first, so a failing run leaves the old file whole.
sched() { # sched MACHINE SOURCE OUTPUT
    "$nesshi" schedule -m "$1" "$2" -I "$kernels/ic" -o "$3"
}
sched os "$kernels/os/dda.pk" "$out/os/dda.s"
sched seq "$kernels/seq/dda.pk" "$out/seq/dda.s"
python3 "$tools/gen_ic.py" > "$work/ic/intersect.pk"
sched ic "$work/ic/intersect.pk" "$out/ic/intersect.s"
sched seq "$kernels/seq/intersect.pk" "$out/seq/intersect.s"
