#!/usr/bin/env python3
"""A description that only inherits a preset, under a name of its own, is that preset: for each
pair of stage presets, nesshi render with copies of them gives the preset's stats JSON byte for
byte (host times aside), and nesshi kernels the preset's rows (issue 25).

usage: preset_copy.py NESSHI OUTDIR
"""
import json
import os
import subprocess
import sys

PAIRS = [("os", "ic", "seq"), ("os-real", "ic-real", "seq-real")]
SCENE = ["tetra:1", "--size", "24", "--grid", "8"]


def render(nesshi, out, name, machines, model):
    path = os.path.join(out, name + ".json")
    cmd = [nesshi, "render", *SCENE, "--model", model, "--stats-json", path, "-q",
           "--os-machine", machines[0], "--ic-machine", machines[1], "--seq-machine", machines[2]]
    subprocess.run(cmd, check=True)
    with open(path) as f:
        stats = json.load(f)
    stats.pop("host", None)
    return json.dumps(stats, sort_keys=True)


def kernel_rows(nesshi, machines):
    text = subprocess.run([nesshi, "kernels", "--os-machine", machines[0], "--ic-machine", machines[1],
                           "--seq-machine", machines[2]], check=True, capture_output=True, text=True).stdout
    return [line for line in text.splitlines() if line and " rows: machine " not in line]  # the rows, not who ran them


def main():
    nesshi, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    failures = 0
    for presets in PAIRS:
        copies = []
        for p in presets:
            path = os.path.join(out, "copy-of-" + p + ".toml")
            with open(path, "w") as f:
                f.write(f'inherits = "{p}"\nname = "my-{p}"\n')
            copies.append(path)
        for model in ("V", "M"):
            same = render(nesshi, out, "preset", presets, model) == render(nesshi, out, "copy", copies, model)
            print(f"{'/'.join(presets)} model {model}: {'same stats' if same else 'DIFFERENT stats'}")
            failures += not same
        same = kernel_rows(nesshi, presets) == kernel_rows(nesshi, copies)
        print(f"{'/'.join(presets)} kernels: {'same rows' if same else 'DIFFERENT rows'}")
        failures += not same
    print("ok: every copy is its preset" if failures == 0 else f"FAIL: {failures} difference(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
