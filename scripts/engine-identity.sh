#!/bin/sh
# Writes every output an engine change must leave byte-identical into OUT: stats JSON, images and
# id buffers of machine runs (models V, M, S; cache; FIFO capacity and latency; 4 PEs; dynamic
# balance; -real machines; the checked engine) and `sim` of every example with every engine.
# Host timings are removed from the JSON. Compare two builds with:
#   scripts/engine-identity.sh build/nesshi /tmp/before   # on the old commit
#   scripts/engine-identity.sh build/nesshi /tmp/after    # on the new one
#   diff -r /tmp/before /tmp/after && echo identical
# With FULL=1 it also runs `paper --size 24` (45 cells) into OUT/paper.
set -eu
NESSHI=$(realpath "$1")
OUT=$2
ROOT=$(cd "$(dirname "$0")/.." && pwd)
rm -rf "$OUT" && mkdir -p "$OUT"
cd "$ROOT"

# The stats JSON without host measurements (the "host" object, any *seconds field) and without a
# paper cell's "digest", which hashes its *seconds fields too (two runs of one build differ there).
strip() {
    python3 - "$1" <<'PY'
import json, sys
def clean(v):
    if isinstance(v, dict):
        return {k: clean(x) for k, x in v.items() if k not in ("host", "digest") and not k.endswith("seconds")}
    return [clean(x) for x in v] if isinstance(v, list) else v
path = sys.argv[1]
with open(path) as f: data = json.load(f)
with open(path, "w") as f: json.dump(clean(data), f, indent=1, sort_keys=True)
PY
}

render() { # NAME ARGS...
    name=$1
    shift
    "$NESSHI" render -q "$@" --stats-json "$OUT/$name.json" -o "$OUT/$name.png" --id-buffer "$OUT/$name.ids"
    strip "$OUT/$name.json"
}

render v-balls balls --model V --grid 20 --size 48
render m-balls balls --model M --grid 20 --size 48
render s-tetra tetra --model S --grid 20 --size 32
render v-tetra tetra --model V --grid 50 --size 48
render v-cache balls --model V --grid 20 --size 48 --cache --cache-size 4096 --no-resident --miss-cycles 30
render v-fifocap rings --model V --grid 20 --size 40 --fifo-capacity 48
render v-fifolat mount --model V --grid 20 --size 40 --fifo-latency 7
render v-pes4 tree --model V --grid 20 --size 48 --pes 4
render v-dynamic balls --model V --grid 20 --size 48 --pes 2 --balance dynamic --epoch 5000
render m-pes2 rings --model M --grid 20 --size 40 --pes 2 --fifo-capacity 36
render v-real balls --model V --grid 20 --size 40 --os-machine os-real --ic-machine ic-real --seq-machine seq-real
render v-checked balls --model V --grid 20 --size 32 --checked --cache --cache-size 2048 --no-resident
render v-quantum1 tetra --model V --grid 20 --size 32 --quantum 1

for s in examples/*.s; do
    base=$(basename "$s" .s)
    fifo=""
    if grep -q 'recv' "$s"; then
        printf '1\n2\n3\n4\n5\n6\n7\n8\n' > "$OUT/$base.in"
        fifo="--fifo-in $OUT/$base.in --fifo-out $OUT/$base.out"
    fi
    for e in fast checked lockstep; do
        # shellcheck disable=SC2086
        "$NESSHI" sim "$s" --engine $e --stats-json "$OUT/$base.$e.json" $fifo > "$OUT/$base.$e.txt" 2>&1 || echo "exit $?" >> "$OUT/$base.$e.txt"
        [ -s "$OUT/$base.$e.json" ] && strip "$OUT/$base.$e.json"
    done
done

if [ "${FULL:-0}" = 1 ]; then
    "$NESSHI" paper -q --size 24 --out "$OUT/paper"
    for f in "$OUT"/paper/cells/*.json; do strip "$f"; done
fi
echo "engine-identity: $(ls "$OUT" | wc -l) files in $OUT" >&2
