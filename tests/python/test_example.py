import os
import subprocess
import sys

import pytest


def test_the_latency_sweep_example_plots(source, tmp_path):
    pytest.importorskip("matplotlib")
    out = tmp_path / "sweep.png"
    r = subprocess.run([sys.executable, source / "examples/python/latency_sweep.py", "--size", "16", "--grid", "8",
                        "--latencies", "1,3", "--out", out], capture_output=True, text=True, env=os.environ)
    assert r.returncode == 0, r.stderr
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    lines = [l for l in r.stdout.splitlines() if l.startswith("float latency")]
    assert len(lines) == 2
