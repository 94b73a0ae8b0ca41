import json
import os
import subprocess
import sys

import nesshi
import numpy as np
import pytest

from conftest import cli


def test_scene_info():
    s = nesshi.scene("balls:1")
    info = s.info()
    assert info["name"] == s.name and info["spheres"] == 10 and info["primitives"] == 11  # and the floor
    assert info["view"]["resolution"] == (512, 512)
    with pytest.raises(nesshi.Error):
        nesshi.scene("nosuch")


def test_render_equals_the_command_line(tmp_path):
    image, stats = nesshi.render("balls:1", model="V", size=24, grid=8, threads=1)
    status, out, err = cli("render", "balls:1", "--model", "V", "--size", "24", "--grid", "8", "--threads", "1",
                           "--stats-json", tmp_path / "s.json", "-o", tmp_path / "i.png", "-q")
    assert status == 0, err
    expected = json.loads((tmp_path / "s.json").read_text())
    for d in (stats, expected):
        d.pop("host", None)  # host seconds differ from run to run
    assert stats == expected
    assert image.shape == (24, 24, 3) and image.dtype == np.uint8
    mpimg = pytest.importorskip("matplotlib.image")
    png = np.rint(mpimg.imread(tmp_path / "i.png")[:, :, :3] * 255).astype(np.uint8)
    assert np.array_equal(image, png)


def test_render_on_a_machine_from_text():
    slow = nesshi.machine('inherits = "ic"\nname = "ic-slow-fmul"\n[latency]\nfmul = 3\n')
    _, fast = nesshi.render("balls:1", size=16, grid=8)
    _, slower = nesshi.render("balls:1", size=16, grid=8, ic_machine=slow)
    assert slower["cycles"]["ic"]["processing"] > fast["cycles"]["ic"]["processing"]


def test_native_and_bad_options():
    image, stats = nesshi.render("balls:1", model="native", size=16)
    assert image.shape == (16, 16, 3) and "cycles" not in stats
    with pytest.raises(ValueError):
        nesshi.render("balls:1", model="W", size=8)
    with pytest.raises(ValueError):
        nesshi.render("balls:1", size=8, cache_size=4096)


def test_render_releases_the_gil():
    import threading

    done = threading.Event()
    t = threading.Thread(target=lambda: (nesshi.render("balls:1", size=48, grid=10, threads=1), done.set()))
    spins = 0
    t.start()
    while not done.is_set():  # runs only while render() does not hold the GIL
        spins += 1
    t.join()
    assert spins > 10000


def test_kernels_scheduled_for_a_machine_file_are_kept_on_disk(tmp_path):
    # A fresh interpreter: the module turns the cache on when it is imported.
    script = ('import nesshi\n'
              'm = nesshi.machine(\'inherits = "ic"\\nname = "ic-cached"\\n[latency]\\nfmul = 3\\n\')\n'
              'nesshi.render("balls:1", size=4, grid=3, ic_machine=m)\n')
    env = dict(os.environ, NESSHI_CACHE_DIR=str(tmp_path / "kernels"))
    subprocess.run([sys.executable, "-c", script], env=env, check=True)
    assert list((tmp_path / "kernels").rglob("*.json")), "no scheduled kernel was kept"
    env["NESSHI_CACHE_DIR"] = ""
    subprocess.run([sys.executable, "-c", script], env=env, check=True)  # off: still renders
