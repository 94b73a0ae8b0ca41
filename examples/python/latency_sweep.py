#!/usr/bin/env python3
"""What if the IC's float units were slower? Renders a small scene on IC machines whose float add and
multiply latency goes from 1 to 4 cycles (the rest as the `ic` preset) and plots each stage's busy
cycles (processing + communication) against that latency.

    PYTHONPATH=build/python python3 examples/python/latency_sweep.py [--out sweep.png] [--size 64]
"""
import argparse

import nesshi


def ic_with_float_latency(cycles):
    return nesshi.machine(f'inherits = "ic"\nname = "ic-float-{cycles}"\n[latency]\nfadd = {cycles}\nfmul = {cycles}\n')


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default="balls:1")
    ap.add_argument("--size", type=int, default=64)
    ap.add_argument("--grid", type=int, default=20)
    ap.add_argument("--latencies", default="1,2,3,4")
    ap.add_argument("--out", default="latency_sweep.png")
    args = ap.parse_args()

    latencies = [int(x) for x in args.latencies.split(",")]
    busy = {"os": [], "ic": [], "sc": []}
    total = []
    for lat in latencies:
        _, stats = nesshi.render(args.scene, model="V", size=args.size, grid=args.grid, ic_machine=ic_with_float_latency(lat))
        cycles = stats["cycles"]
        for stage in busy:
            busy[stage].append(cycles[stage]["processing"] + cycles[stage]["communication"])
        total.append(cycles["total"])
        print(f"float latency {lat}: total {cycles['total']} cycles, IC busy {busy['ic'][-1]}")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for stage, label in (("os", "OS (3DDDA)"), ("ic", "IC (intersection)"), ("sc", "SC (shading)")):
        ax.plot(latencies, [c / 1e6 for c in busy[stage]], marker="o", label=f"{label} busy")
    ax.plot(latencies, [c / 1e6 for c in total], marker="s", linestyle="--", color="black", label="whole render")
    ax.set_xlabel("IC float add / multiply latency (cycles)")
    ax.set_ylabel("million cycles")
    ax.set_xticks(latencies)
    ax.set_ylim(bottom=0)
    ax.set_title(f"{args.scene}, {args.size}x{args.size}, grid {args.grid}, model V")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
