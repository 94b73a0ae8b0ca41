# The Python module's tests run by ctest (python.pytest) with PYTHONPATH at build/python, NESSHI at
# the command line tool and NESSHI_SOURCE at the source tree: each checks the module against the
# command line's own outputs.
import json
import os
import subprocess
from pathlib import Path

import pytest

SOURCE = Path(os.environ.get("NESSHI_SOURCE", Path(__file__).resolve().parents[2]))
NESSHI = os.environ.get("NESSHI", str(SOURCE / "build" / "nesshi"))


def cli(*args, cwd=None):
    """Runs `nesshi ARGS`; returns (exit status, stdout, stderr)."""
    r = subprocess.run([NESSHI, *map(str, args)], capture_output=True, text=True, cwd=cwd)
    return r.returncode, r.stdout, r.stderr


def cli_json(*args):
    status, out, err = cli(*args)
    assert status == 0, err
    return json.loads(out)


@pytest.fixture
def source():
    return SOURCE
