#!/bin/sh
# The kernels.regenerate CTest: regenerates every kernel under OUTDIR with today's tools
# (build.sh OUTDIR) and compares each with the committed kernels/*/*.s, byte for byte; on a
# difference it prints the diff and fails. Usage: kernels/tools/check.sh OUTDIR
set -eu
[ $# -eq 1 ] || { echo "usage: kernels/tools/check.sh OUTDIR" >&2; exit 2; }
kernels="$(cd "$(dirname "$0")/.." && pwd)"
out="$1"
rm -rf "$out"
sh "$kernels/tools/build.sh" "$out"

generated="$(cd "$out" && find . -name '*.s' | sed 's|^\./||' | sort)"
committed="$(cd "$kernels" && find . -mindepth 2 -maxdepth 2 -name '*.s' | sed 's|^\./||' | sort)"
status=0
if [ "$generated" != "$committed" ]; then
    echo "error: build.sh generates [$(echo $generated)] but kernels/ holds [$(echo $committed)]" >&2
    status=1
fi
for f in $generated; do
    if cmp -s "$kernels/$f" "$out/$f"; then
        echo "kernels/$f: same as generated"
    else
        echo "error: kernels/$f differs from what kernels/tools/build.sh generates ($out/$f):" >&2
        diff -u "$kernels/$f" "$out/$f" >&2 || true
        status=1
    fi
done
[ $status -eq 0 ] || echo "regenerate the committed kernels with kernels/tools/build.sh" >&2
exit $status
