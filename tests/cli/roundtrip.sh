#!/usr/bin/env bash
# roundtrip.sh NESSHI MACHINE FILE.s OUTPREFIX: asm -> dis -> asm must give a byte-identical object.
set -eu
nesshi=$1 machine=$2 src=$3 out=$4
mkdir -p "$(dirname "$out")"
"$nesshi" asm -m "$machine" "$src" -o "$out.o"
"$nesshi" dis -m "$machine" "$out.o" >"$out.dis.s"
"$nesshi" asm -m "$machine" "$out.dis.s" -o "$out.2.o"
cmp "$out.o" "$out.2.o"
