#!/bin/bash
# The engines agree on a fault: `sim --engine E` for each E given prints the same first line
# (but for the engine's name) and the same statistics JSON. A dynamic rule only the checked
# engine sees is reported by lock-step at the checked engine's count, not after the faulting
# bundle the fast engine issued.
# Usage: sim_engines_agree.sh NESSHI WORKDIR EXPECTED_CYCLES PROGRAM "ENGINES" [sim options...]
nesshi=$1 dir=$2 cycles=$3 prog=$4 engines=$5; shift 5
mkdir -p "$dir"
first=""
for e in $engines; do
  "$nesshi" sim "$prog" --engine "$e" --stats-json "$dir/$e.json" "$@" > "$dir/$e.out" 2>&1
  rc=$?
  [ $rc -eq 3 ] || { echo "$e: exit $rc, expected 3"; cat "$dir/$e.out"; exit 1; }
  line=$(head -1 "$dir/$e.out")
  case "$line" in
    *": stopped after $cycles cycles ($e engine): "*) ;;
    *) echo "$e: first line '$line', expected 'stopped after $cycles cycles ($e engine): <why>'"; exit 1 ;;
  esac
  if [ -z "$first" ]; then first=$e
  else
    cmp -s "$dir/$first.json" "$dir/$e.json" || { echo "$first and $e statistics differ:"; diff "$dir/$first.json" "$dir/$e.json"; exit 1; }
    a=$(head -1 "$dir/$first.out" | sed "s/($first engine)//") b=$(echo "$line" | sed "s/($e engine)//")
    [ "$a" = "$b" ] || { echo "first lines differ: '$a' and '$b'"; exit 1; }
  fi
done
