#!/usr/bin/env python3
"""Compiled runs built at run time (iss/compiled.hpp: NESSHI_RUNTIME_COMPILE) for a user's machine.

A loop of 3.6 M cycles on a copy of the `seq` preset with another branch penalty, which the build
compiled nothing for: under `wait:1` it starts on the interpreter and switches to its compiled runs
in mid-run (after its first slice), with the interpreter's statistics and memory, also under
lock-step; the runs land in the cache once, with nothing left beside them, and a later run in the
default mode loads them; a damaged object is removed and compiled again; a cache that cannot be
written is a warning; in the default mode a run shorter than its compilation leaves the object
for the next one; NESSHI_COMPILED=0 and NESSHI_RUNTIME_COMPILE=0 leave them unused; two
processes compiling one program at once make one object; a compiler that fails is a warning and
the run goes on interpreted, and the next run does not compile it again; a missing compiler is a
warning; another compiler gets a cache folder of its own; under NESSHI_COMPILED_CACHE_MB=0 a new
object replaces the old one, and a limit that is no number is a warning; a model M render
(several processors, the kernel workloads) gives the interpreter's statistics; a 2-cycle receive
inside a run (the generator's Ring<R...> landing, which no built-in kernel has) gives them too.
usage: runtime_compile.py NESSHI SOURCE_DIR OUTDIR
"""
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

nesshi, src, out = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3])
shutil.rmtree(out, ignore_errors=True)
out.mkdir(parents=True)
machine = out / "myseq.toml"
machine.write_text((src / "isa/machines/seq.toml").read_text()
                   .replace('name = "seq"', 'name = "myseq"').replace("branch_penalty = 0", "branch_penalty = 2"))
program = out / "long.s"
program.write_text("""# machine: seq
        .data 0x200
total:  .word 0
        .text
        li r2, 600000
        li r3, 0
loop:   add r3, r3, r2
        xor r3, r3, r2
        addi r2, r2, -1
        bnez r2, loop
        li r5, total
        sw r3, 0(r5)
        halt
""")
hot = out / "hot.s" # 72 M cycles: past the default mode's 2^26
hot.write_text(program.read_text().replace("li r2, 600000", "li r2, 12000000"))
failures = []
base_env = {k: v for k, v in os.environ.items() if k not in ("NESSHI_COMPILED", "NESSHI_CXX")}


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAILED:", what)


def run(mode, cache, *args, engine="fast", env=None, name="run", source=program):
    """nesshi sim of the loop: (first line of the report, stats JSON, dumped total, stderr)."""
    stats = out / f"{name}.json"
    e = dict(base_env, NESSHI_RUNTIME_COMPILE=mode, XDG_CACHE_HOME=str(out / cache), **(env or {}))
    r = subprocess.run([nesshi, "sim", "-m", str(machine), str(source), "--engine", engine, "--stats-json", str(stats),
                        "--dump", "total:1:i32", *args], env=e, capture_output=True, text=True)
    check(r.returncode == 0, f"{name}: exit {r.returncode}: {r.stderr}")
    lines = r.stdout.splitlines()
    return (lines[0] if lines else ""), (stats.read_text() if stats.exists() else ""), lines[-1:], r.stderr


def cache_files(cache):
    """The files of the cache's build folders, their headers and lock files (empty, kept) aside."""
    d = out / cache / "nesshi/compiled"
    return sorted(f.name for b in d.iterdir() for f in b.iterdir()
                  if f.name != "include" and not f.name.endswith(".lock")) if d.exists() else []


interpreted = run("0", "cache", name="interpreted")
check(interpreted[0].endswith("(fast engine)"), f"NESSHI_RUNTIME_COMPILE=0: {interpreted[0]}")
check(not (out / "cache").exists(), "NESSHI_RUNTIME_COMPILE=0 wrote a cache")

switched = run("wait:1", "cache", name="switched")
check(switched[0].endswith("(fast engine, compiled runs)"), f"wait:1: {switched[0]}")
check(switched[1:3] == interpreted[1:3], "wait:1: statistics or memory differ from the interpreter's")
objects = cache_files("cache")
check(len(objects) == 1 and objects[0].endswith(".so"), f"the cache holds {objects}, not one object")

loaded = run("1", "cache", name="loaded")
check(loaded[0].endswith("(fast engine, compiled runs)"), f"the default mode did not load the cache: {loaded[0]}")
check(loaded[1:3] == interpreted[1:3], "loaded runs: statistics or memory differ")
# A damaged object (cut short from outside; dlopen would die of SIGBUS on it): removed, warned of,
# compiled again.
so = next((out / "cache/nesshi/compiled").glob("*/*.so"))
so.write_bytes(so.read_bytes()[:1000])
mended = run("wait", "cache", name="damaged")
check(mended[0].endswith("(fast engine, compiled runs)") and mended[1:3] == interpreted[1:3], "a damaged object")
check("removed damaged compiled runs" in mended[3], f"no warning of the damaged object: {mended[3]!r}")
check(so.stat().st_size > 1000, "the damaged object was not compiled again")
off = run("1", "cache", env={"NESSHI_COMPILED": "0"}, name="compiled-off")
check(off[0].endswith("(fast engine)"), f"NESSHI_COMPILED=0 still used compiled runs: {off[0]}")
check(run("0", "cache", name="runtime-off")[0].endswith("(fast engine)"), "NESSHI_RUNTIME_COMPILE=0 loaded the cache")
check(run("1", "cache", engine="checked", name="checked")[0].endswith("(checked engine)"), "the checked engine")
# The cache's size limit (NESSHI_COMPILED_CACHE_MB): another program compiled under a limit of 0
# takes the place of the object there (the least recently loaded goes; the one just made stays).
other = out / "other.s"
other.write_text(program.read_text().replace("li r2, 600000", "li r2, 600001"))
first_object = cache_files("cache")
trimmed = run("wait", "cache", env={"NESSHI_COMPILED_CACHE_MB": "0"}, name="trimmed", source=other)
check(trimmed[0].endswith("(fast engine, compiled runs)"), f"under a limit of 0: {trimmed[0]}")
now = cache_files("cache")
check(len(now) == 1 and now != first_object, f"a limit of 0 left {now} (before: {first_object})")
bad_limit = run("1", "cache", env={"NESSHI_COMPILED_CACHE_MB": "lots"}, name="bad-limit", source=other)
check("NESSHI_COMPILED_CACHE_MB=lots is not a number of megabytes" in bad_limit[3], f"no warning: {bad_limit[3]!r}")
check(bad_limit[0].endswith("(fast engine, compiled runs)"), f"a bad limit stopped the cache: {bad_limit[0]}")
run("wait:1", "cache-lockstep", "-q", engine="lockstep", name="lockstep") # a divergence exits 3

# Two processes compiling one program at once: one object, nothing else left.
envs = [dict(base_env, NESSHI_RUNTIME_COMPILE="wait", XDG_CACHE_HOME=str(out / "cache-race"))] * 2
both = [subprocess.Popen([nesshi, "sim", "-m", str(machine), str(program)], env=e, stdout=subprocess.PIPE, text=True)
        for e in envs]
for p in both:
    first = p.communicate()[0].splitlines()[0]
    check(p.returncode == 0 and first.endswith("(fast engine, compiled runs)"), f"concurrent compilation: {first}")
check(len(cache_files("cache-race")) == 1, f"concurrent compilation left {cache_files('cache-race')}")

# A compiler that fails: a warning that names its log, the run goes on interpreted.
failed = run("wait", "cache-failing", env={"NESSHI_CXX": "false"}, name="failing")
check(failed[0].endswith("(fast engine)") and failed[1:3] == interpreted[1:3], "a failing compiler changed the run")
check("compiling the runs of a program failed (see" in failed[3], f"no warning of the failure: {failed[3]!r}")
check([f for f in cache_files("cache-failing") if not f.endswith(".log")] == [], "a failed compilation left files")
again = run("wait", "cache-failing", env={"NESSHI_CXX": "false"}, name="failing-again")
check("failed to compile before (see" in again[3] and again[1:3] == interpreted[1:3], f"a failure compiled again: {again[3]!r}")
missing = run("wait", "cache-missing", env={"NESSHI_CXX": "no-such-compiler"}, name="no-compiler")
check("NESSHI_CXX=no-such-compiler is not a program" in missing[3], f"no warning of a missing compiler: {missing[3]!r}")

# A cache that cannot be written: a warning, the run interpreted.
(out / "not-a-folder").write_text("")
unwritable = run("wait", "not-a-folder", name="unwritable")
check(unwritable[0].endswith("(fast engine)") and unwritable[1:3] == interpreted[1:3], "an unwritable cache")
check("cannot write" in unwritable[3], f"no warning of the unwritable cache: {unwritable[3]!r}")

# Another compiler (clang++ is the default when installed): a cache folder of its own, same results.
if shutil.which("c++"):
    other = run("wait", "cache", env={"NESSHI_CXX": "c++"}, name="other-compiler")
    check(other[0].endswith("(fast engine, compiled runs)") and other[1:3] == interpreted[1:3], "NESSHI_CXX=c++")
    check(len(list((out / "cache/nesshi/compiled").iterdir())) == 2, "a compiler without a cache folder of its own")


# The default mode: a run that ends before its compilation starts it, the compiler outlives it,
# and the next run loads the object.
def sim_hot():
    e = dict(base_env, NESSHI_RUNTIME_COMPILE="1", XDG_CACHE_HOME=str(out / "cache-background"))
    r = subprocess.run([nesshi, "sim", "-m", str(machine), str(hot)], env=e, capture_output=True, text=True)
    check(r.returncode == 0, f"background: exit {r.returncode}: {r.stderr}")
    return r.stdout.splitlines()[0] if r.stdout else ""


sim_hot()
for _ in range(600):
    if any(f.endswith(".so") for f in cache_files("cache-background")): # renamed in whole
        break
    time.sleep(0.1)
check(sim_hot().endswith("(fast engine, compiled runs)"), f"background: the next run did not load: {cache_files('cache-background')}")


# The machine: a model M render on the user's machine (the OS and IC stages run seq programs).
def render(mode, name):
    stats = out / f"{name}.json"
    e = dict(base_env, NESSHI_RUNTIME_COMPILE=mode, XDG_CACHE_HOME=str(out / "cache-render"))
    r = subprocess.run([nesshi, "render", "tetra:1", "--size", "16", "--grid", "4", "--model", "M", "--seq-machine",
                        str(machine), "-o", str(out / f"{name}.png"), "--stats-json", str(stats)],
                       env=e, capture_output=True, text=True)
    check(r.returncode == 0, f"render {name}: exit {r.returncode}: {r.stderr}")
    s = json.loads(stats.read_text())
    s.pop("host", None)
    return s, (out / f"{name}.png").read_bytes()


check(render("wait:1", "render-compiled") == render("0", "render-interpreted"), "model M: compiled runs changed the render")
check(len(cache_files("cache-render")) >= 1, "model M: nothing compiled")


# A run whose head copy holds a receive of latency 2 (a copy of seq with 2-cycle FIFO operations):
# the generator lands its slot as writes it knows (compiled.hpp Ring<R...>), a form no built-in
# kernel has. A compiler wrapper finds it in the generated source; the interpreter's statistics
# and memory check it (a Ring that landed nothing fails here). Lock-step, which steps one bundle
# at a time, mostly runs the copy that probes.
fifo2 = out / "fifo2.toml"
fifo2.write_text((src / "isa/machines/seq.toml").read_text()
                 .replace('name = "seq"', 'name = "seqfifo2"').replace("fifo = 1", "fifo = 2"))
receiver = out / "receiver.s" # the first loop, its words received
receiver.write_text(program.read_text().replace("li r2, 600000", "li r2, 400000")
                    .replace("loop:   add r3, r3, r2\n        xor r3, r3, r2\n",
                             "loop:   recv r4, 0\n        nop\n        add r3, r3, r4\n"))
words = out / "words.txt"
words.write_text("\n".join(str(i * 7919 % 100003) for i in range(400000)) + "\n")
ring_seen = out / "ring-seen"
wrapper = out / "cxx-ring.sh"
wrapper.write_text(f"""#!/bin/sh
for a in "$@"; do case "$a" in *.cpp) grep -q "Ring<" "$a" && touch '{ring_seen}';; esac; done
if command -v clang++ >/dev/null; then exec clang++ "$@"; else exec c++ "$@"; fi
""")
wrapper.chmod(0o755)


def sim_receiver(mode, engine, name):
    """nesshi sim of the receiving loop: (first line of the report, stats JSON, dumped total)."""
    stats = out / f"{name}.json"
    e = dict(base_env, NESSHI_RUNTIME_COMPILE=mode, NESSHI_CXX=str(wrapper), XDG_CACHE_HOME=str(out / "cache-ring"))
    r = subprocess.run([nesshi, "sim", "-m", str(fifo2), str(receiver), "--fifo-in", str(words), "--engine", engine,
                        "--stats-json", str(stats), "--dump", "total:1:i32"], env=e, capture_output=True, text=True)
    check(r.returncode == 0, f"{name}: exit {r.returncode}: {r.stderr}")
    lines = r.stdout.splitlines()
    return (lines[0] if lines else ""), (stats.read_text() if stats.exists() else ""), lines[-1:]


ring_interpreted = sim_receiver("0", "fast", "ring-interpreted")
ring_compiled = sim_receiver("wait:1", "fast", "ring-compiled")
check(ring_compiled[0].endswith("(fast engine, compiled runs)"), f"2-cycle receive: {ring_compiled[0]}")
check(ring_seen.exists(), "the runs generated for a 2-cycle receive have no Ring<R...> landing")
check(ring_compiled[1:] == ring_interpreted[1:], "2-cycle receive: compiled runs changed the statistics or memory")
sim_receiver("wait:1", "lockstep", "ring-lockstep")  # a divergence exits 3

if failures:
    sys.exit(f"{len(failures)} check(s) failed")
print("runtime compilation: all checks passed")
