#!/bin/sh
# Regenerates the scheduled kernels from their sources (run from kernels/).
set -e
cd "$(dirname "$0")/.."
python3 tools/pack.py -m os os/dda.pk > os/dda.s
python3 tools/pack.py -m seq seq/dda.pk > seq/dda.s
python3 tools/gen_ic.py > ic/intersect.pk
python3 tools/pack.py -m ic ic/intersect.pk > ic/intersect.s

python3 tools/pack.py -m seq seq/intersect.pk > seq/intersect.s
