#!/usr/bin/env python3
"""Invariants of `nesshi render --trace-json` against its --stats-json: every busy fraction is in
[0, 1]; each stage of each PE has process/thread names and "X" slices (processing,
communication, wait) that do not overlap and tile its time from 0 to the PE's end; summed over
the PEs, the slices of each kind per stage equal the statistics' cycles of that stage.
Usage: check_trace.py TRACE_JSON STATS_JSON"""
import json, sys
from collections import defaultdict

trace = json.load(open(sys.argv[1]))
stats = json.load(open(sys.argv[2]))
ev = trace["traceEvents"]
errors = []
names = {(e["pid"], e.get("tid")): e["args"]["name"] for e in ev if e["ph"] == "M" and e["name"] in ("process_name", "thread_name")}
stage_tid = {"OS": 0, "IC": 1, "SC (modelled)": 2}
pids = sorted({e["pid"] for e in ev})
if len(pids) != len(stats["cycles"]["pe"]):
    errors.append(f"{len(pids)} PEs in the trace, {len(stats['cycles']['pe'])} in the statistics")
tracks = defaultdict(list)
for e in ev:
    if e["ph"] == "X":
        tracks[(e["pid"], e["tid"])].append(e)
    if e["ph"] == "C" and e["name"].startswith("activity"):
        for k, v in e["args"].items():
            if not 0.0 <= v <= 1.0:
                errors.append(f"busy fraction {k} = {v} at {e['ts']} (PE {e['pid']})")
totals = defaultdict(int)
for p in pids:
    if names.get((p, None)) != f"PE {p}":
        errors.append(f"PE {p}: no process name")
    end = stats["cycles"]["pe"][p]
    for stage, tid in stage_tid.items():
        if names.get((p, tid)) != stage:
            errors.append(f"PE {p}: thread {tid} is not named {stage}")
        t = 0
        for e in sorted(tracks[(p, tid)], key=lambda e: e["ts"]):
            if e["ts"] != t:
                errors.append(f"PE {p} {stage}: slice at {e['ts']}, expected {t} (gap or overlap)")
            if e["dur"] <= 0 or e["name"] not in ("processing", "communication", "wait"):
                errors.append(f"PE {p} {stage}: bad slice {e}")
            t = e["ts"] + e["dur"]
            totals[(stage, e["name"])] += e["dur"]
        if t != end:
            errors.append(f"PE {p} {stage}: slices end at {t}, the PE at {end}")
for stage, key in (("OS", "os"), ("IC", "ic"), ("SC (modelled)", "sc")):
    for kind in ("processing", "communication", "wait"):
        if totals[(stage, kind)] != stats["cycles"][key][kind]:
            errors.append(f"{stage} {kind}: slices {totals[(stage, kind)]}, statistics {stats['cycles'][key][kind]}")
if errors:
    print("\n".join(errors[:30]))
    sys.exit(1)
print(f"ok: {len(ev)} events, {sum(len(v) for v in tracks.values())} slices, {len(pids)} PEs")
