#!/usr/bin/env python3
"""The quantum is a performance knob only: --quantum 1, the default and --quantum 100000 give the
same stats JSON (host times and the quantum option itself aside) for each case. Model S has no
quantum (nesshi render rejects it there): its three stages share one clock.

usage: quantum_exact.py NESSHI OUTDIR
"""
import json
import os
import subprocess
import sys

# Scenes, models, PE counts and FIFO options (capacity, latency); small so all run in seconds.
CASES = [
    ["tetra:1", "--size", "24", "--grid", "8", "--model", "V"],
    ["tetra:1", "--size", "24", "--grid", "8", "--model", "M"],
    ["tetra:1", "--size", "16", "--grid", "8", "--model", "M", "--pes", "2"],
    ["balls:1", "--size", "20", "--grid", "8", "--model", "V", "--pes", "2"],
    ["balls:1", "--size", "20", "--grid", "8", "--model", "V", "--fifo-latency", "3"],
    ["balls:1", "--size", "20", "--grid", "8", "--model", "V", "--fifo-capacity", "64"],
    ["balls:1", "--size", "20", "--grid", "8", "--model", "M", "--fifo-capacity", "48", "--fifo-latency", "2"],
    ["gears:1", "--size", "16", "--grid", "8", "--model", "V", "--pes", "4"],
    ["mount:1", "--size", "16", "--grid", "6", "--model", "V", "--pes", "2", "--balance", "dynamic", "--epoch", "3000"],
    ["mount:1", "--size", "16", "--grid", "6", "--model", "M", "--pes", "4", "--fifo-capacity", "36"],
]
QUANTA = ["1", None, "100000"]  # None: the default


def strip(stats):
    stats.pop("host", None)
    stats.get("machine", {}).pop("quantum", None)
    return stats


def main():
    nesshi, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    failed = 0
    for i, case in enumerate(CASES):
        runs = []
        for q in QUANTA:
            path = os.path.join(out, f"q{i}-{q or 'default'}.json")
            cmd = [nesshi, "render", *case, "-q", "--stats-json", path, "-o", os.path.join(out, f"q{i}.png")]
            if q:
                cmd += ["--quantum", q]
            subprocess.run(cmd, check=True)
            with open(path) as f:
                runs.append(strip(json.load(f)))
        cycles = [r["cycles"]["total"] for r in runs]
        same = all(r == runs[0] for r in runs)
        print(f"{'ok  ' if same else 'DIFF'} {' '.join(case)}: cycles {cycles}")
        if not same:
            failed += 1
            for q, r in zip(QUANTA[1:], runs[1:]):
                keys = [k for k in runs[0] if runs[0].get(k) != r.get(k)]
                print(f"     quantum {q or 'default'} differs from quantum 1 in {keys}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
