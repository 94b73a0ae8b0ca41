#!/bin/sh
# The kernels scheduled for a machine file are kept on disk (kbuild/schedule_cache.hpp): a run
# writes them under NESSHI_CACHE_DIR, a second run reads them (and prints the same), a damaged
# cache file is scheduled again (same output, no error), another build's folder goes after 30
# days unused, and an empty NESSHI_CACHE_DIR writes nothing. usage: schedule_cache.sh NESSHI OUTDIR
set -eu
nesshi=$1 out=$2
rm -rf "$out"
mkdir -p "$out"
run() { # run CACHE_DIR JSON
    NESSHI_CACHE_DIR=$1 "$nesshi" kernels --os-machine os-real --json "$2" >/dev/null 2>&1
}
run "$out/cache" "$out/first.json"
files=$(ls "$out/cache"/*/*.json | wc -l)
[ "$files" -ge 1 ] || { echo "FAILED: nothing cached"; exit 1; }
run "$out/cache" "$out/cached.json"
cmp "$out/first.json" "$out/cached.json" || { echo "FAILED: the cached kernels measure differently"; exit 1; }
# What the render says of its kernel's loops comes from the cache file, not from scheduling again.
for f in "$out/cache"/*/*.json; do sed 's/"stages":[0-9]*/"stages":99/g' "$f" >"$f.new" && mv "$f.new" "$f"; done
NESSHI_CACHE_DIR="$out/cache" "$nesshi" render tetra:1 --size 8 --grid 4 --model V --os-machine os-real \
    -o "$out/r.png" >"$out/render.txt" 2>&1
grep -q "99 stages" "$out/render.txt" || { echo "FAILED: the render did not read the cache"; cat "$out/render.txt"; exit 1; }
for f in "$out/cache"/*/*.json; do echo '{"key": "damaged' >"$f"; done
run "$out/cache" "$out/damaged.json"
cmp "$out/first.json" "$out/damaged.json" || { echo "FAILED: a damaged cache changed the kernels"; exit 1; }
grep -q '"text"' "$out/cache"/*/*.json || { echo "FAILED: the damaged files were not written again"; exit 1; }
# Other builds' folders go once unused for 30 days; a recent one stays.
mkdir -p "$out/cache/old-build" "$out/cache/recent-build"
touch "$out/cache/old-build/x.json" "$out/cache/recent-build/x.json"
touch -d "40 days ago" "$out/cache/old-build"
run "$out/cache" "$out/pruned.json"
[ ! -e "$out/cache/old-build" ] || { echo "FAILED: an old build's folder was kept"; exit 1; }
[ -e "$out/cache/recent-build/x.json" ] || { echo "FAILED: a recent build's folder was removed"; exit 1; }
mkdir -p "$out/home"
HOME="$out/home" XDG_CACHE_HOME= NESSHI_CACHE_DIR= "$nesshi" kernels --os-machine os-real >/dev/null 2>&1
[ -z "$(find "$out/home" -type f)" ] || { echo "FAILED: NESSHI_CACHE_DIR= still wrote a cache"; exit 1; }
echo "ok: $files scheduled kernels cached, read back, rewritten when damaged, old builds pruned"
