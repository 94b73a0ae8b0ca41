#!/usr/bin/env python3
"""`nesshi debug` on a terminal (a pty): Ctrl-C during `continue` stops the run and keeps the
state, Ctrl-C at the prompt clears the line, Ctrl-D quits with status 0; TAB completes; the
history is written to $HOME/.nesshi_history and read by the next session (Ctrl-P recalls it);
--script mode and a session without HOME write none.
Usage: debug_interactive.py NESSHI PROGRAM WORKDIR"""
import os, pty, re, select, shutil, subprocess, sys, time

nesshi, prog, work = sys.argv[1:4]
shutil.rmtree(work, ignore_errors=True)
home = os.path.join(work, "home")
os.makedirs(home)
hist = os.path.join(home, ".nesshi_history")


def fail(msg, out=b""):
    print("FAIL:", msg)
    print(out.decode(errors="replace"))
    sys.exit(1)


class Session:
    def __init__(self, env):
        self.pid, self.fd = pty.fork()
        if self.pid == 0:
            os.execve(nesshi, [nesshi, "debug", prog], env)
        self.out = b""

    def expect(self, pat, timeout=20):
        end = time.time() + timeout
        while time.time() < end:
            if re.search(pat, self.out):
                m = re.search(pat, self.out)
                self.out = self.out[m.end():]
                return m
            r, _, _ = select.select([self.fd], [], [], 0.1)
            if r:
                try:
                    data = os.read(self.fd, 4096)
                except OSError:
                    data = b""
                if not data:
                    break
                self.out += data
        fail(f"no {pat!r} in the output", self.out)

    def send(self, b, pause=0.2):
        os.write(self.fd, b)
        time.sleep(pause)

    def wait(self):
        end = time.time() + 20
        while time.time() < end:
            pid, status = os.waitpid(self.pid, os.WNOHANG)
            if pid:
                return os.waitstatus_to_exitcode(status)
            time.sleep(0.05)
        fail("the session did not end", self.out)


env = {k: v for k, v in os.environ.items() if k != "XDG_STATE_HOME"}
env["HOME"] = home
env["TERM"] = "dumb"

s = Session(env)
s.expect(rb"\(nesshi\) ")
s.send(b"continue\r", 0.5)
s.send(b"\x03")  # Ctrl-C during the run
m = s.expect(rb"interrupted: cycle (\d+), pc 1")
cycle = int(m.group(1))
s.expect(rb"\(nesshi\) ")
s.send(b"info regs p\r")
m = s.expect(rb"pc 1  cycle (\d+)  status running")
if int(m.group(1)) != cycle:
    fail(f"the state moved after the interrupt: cycle {cycle}, then {m.group(1)}")
s.expect(rb"\(nesshi\) ")
s.send(b"brea")
s.send(b"\x03")  # Ctrl-C at the prompt: the line is dropped
s.send(b"step\r")
m = s.expect(rb"cycle (\d+), pc 1")
if int(m.group(1)) != cycle + 1:
    fail(f"step after the interrupt: cycle {m.group(1)}, expected {cycle + 1}")
s.expect(rb"\(nesshi\) ")
s.send(b"info infl\t\r")  # TAB completes "inflight"
s.expect(rb"(no writes|in flight) ")
s.expect(rb"\(nesshi\) ")
s.send(b"\x04")  # Ctrl-D
rc = s.wait()
if rc != 0:
    fail(f"Ctrl-D: exit status {rc}, expected 0", s.out)
if b"unknown command" in s.out:
    fail("a line cleared by Ctrl-C ran", s.out)
text = open(hist).read() if os.path.exists(hist) else fail(f"no history file {hist}")
for cmd in ("continue", "step"):
    if cmd not in text:
        fail(f"history lacks {cmd!r}:\n{text}")
if "brea" in text.replace("break", ""):
    fail(f"history holds the cleared line:\n{text}")

# The next session reads it: Ctrl-P recalls the last command (info inflight).
s = Session(env)
s.expect(rb"\(nesshi\) ")
s.send(b"\x10\r")
s.expect(rb"no writes in flight at cycle 0")
s.send(b"quit\r")
if s.wait() != 0:
    fail("quit: non-zero exit status", s.out)

# --script mode writes no history.
home2 = os.path.join(work, "home2")
os.makedirs(home2)
script = os.path.join(work, "script")
open(script, "w").write("step\nquit\n")
r = subprocess.run([nesshi, "debug", prog, "--script", script], env=dict(env, HOME=home2), capture_output=True)
if r.returncode != 0 or os.listdir(home2):
    fail(f"--script: exit {r.returncode}, HOME holds {os.listdir(home2)}", r.stdout + r.stderr)

# Without HOME: no history, and the session still works.
env3 = {k: v for k, v in env.items() if k != "HOME"}
s = Session(env3)
s.expect(rb"\(nesshi\) ")
s.send(b"step\r")
s.expect(rb"cycle 1, pc 1")
s.send(b"\x04")
if s.wait() != 0:
    fail("no HOME: non-zero exit status", s.out)
print("ok")
