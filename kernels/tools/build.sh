#!/bin/sh
# Regenerates the scheduled kernels from their sources with the Python tools beside this script.
#   kernels/tools/build.sh          rewrites the committed os/dda.s, seq/dda.s, ic/intersect.s and
#                                   seq/intersect.s in place; the generated ic/intersect.pk (the
#                                   IC kernel before scheduling) goes to a temporary directory
#   kernels/tools/build.sh OUTDIR   writes the same files, and ic/intersect.pk, under OUTDIR
#                                   instead (the kernels.regenerate CTest compares them)
set -eu
kernels="$(cd "$(dirname "$0")/.." && pwd)"
tools="$kernels/tools"
if ! command -v python3 >/dev/null 2>&1; then
    echo "kernels/tools/build.sh: error: python3 not found; the kernel generators need it" \
         "(scripts/install-deps.sh installs it)" >&2
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

# Each output is written beside its target first, so a failing tool leaves the old file whole.
pack() { # pack MACHINE SOURCE OUTPUT
    python3 "$tools/pack.py" -m "$1" "$2" > "$3.tmp"
    mv "$3.tmp" "$3"
}
pack os "$kernels/os/dda.pk" "$out/os/dda.s"
pack seq "$kernels/seq/dda.pk" "$out/seq/dda.s"
python3 "$tools/gen_ic.py" > "$work/ic/intersect.pk"
pack ic "$work/ic/intersect.pk" "$out/ic/intersect.s"
pack seq "$kernels/seq/intersect.pk" "$out/seq/intersect.s"
