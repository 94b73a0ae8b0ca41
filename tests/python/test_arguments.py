# Wrong arguments and misuse: each a Python exception with a message (never a crash, a hang, a
# generic "Unable to cast" RuntimeError, or a file written for a machine argument).
import _thread
import glob
import threading
import time

import nesshi
import numpy as np
import pytest

LOOP = "start: { jmp start }\n"  # runs forever


def test_exception_classes_are_nesshis_and_library_failures_are_nesshi_error(source):
    assert nesshi.Error.__module__ == "nesshi" and nesshi.AssemblyError.__module__ == "nesshi"
    with pytest.raises(nesshi.Error, match="cycle limit"):  # a std::runtime_error in the library
        nesshi.render("balls:1", model="S", size=4, grid=3, max_cycles=10)
    with pytest.raises(nesshi.Error, match="not a loop"):
        nesshi.loop_report(nesshi.assemble(source / "examples/dot3.s"), "nope")


def test_a_machine_compares_with_anything():
    ic = nesshi.machine("ic")
    assert ic != 5 and ic not in [None, "ic"] and ic == nesshi.machine("ic")
    text = nesshi.machine('inherits = "ic"\nname = "ic2"\n')
    assert repr(text) == "<nesshi.Machine 'ic2' from TOML text>"


def test_a_machine_named_like_a_path_renders_and_writes_no_file(tmp_path):
    name = f"../../../../../../{tmp_path}/escaped".replace("//", "/")
    m = nesshi.machine(f'inherits = "ic"\nname = "{name}"\n[latency]\nfmul = 3\n')
    image, _ = nesshi.render("balls:1", size=4, grid=3, ic_machine=m)
    assert image.shape == (4, 4, 3) and glob.glob(str(tmp_path / "escaped*")) == []


def test_a_missing_source_file_is_said_so():
    with pytest.raises(nesshi.Error, match="examples/nope.s: error: cannot open"):
        nesshi.assemble("examples/nope.s")
    with pytest.raises(nesshi.Error, match="cannot open"):
        nesshi.pipeline("nope.sa")
    assert nesshi.assemble("halt").bundles == 1  # one word of code is still code
    for wrong in (5, None, b"halt"):
        with pytest.raises(TypeError, match="source is text"):
            nesshi.assemble(wrong)


def test_values_that_do_not_fit_raise_value_error(source):
    p = nesshi.Processor(nesshi.assemble(source / "examples/fifo_echo.s"))
    for words, dtype in (([-1], "u32"), ([2**31], "i32"), (["x"], "f32")):
        with pytest.raises(ValueError, match="value 0"):
            p.feed(0, words, dtype=dtype)
    with pytest.raises(ValueError, match="r1 takes an int"):
        p.set_reg("r1", 2**40)
    with pytest.raises(ValueError, match="r1 takes an int"):
        p.set_reg("r1", 1.5)
    p.set_reg("f1", np.float32(1.5))  # a numpy float is a float, not bits
    assert p.reg("f1") == 1.5
    p.set_reg("f2", 0x3FC00000)  # an int is the bits
    assert p.reg("f2") == 1.5


def test_breakpoints_take_code_labels_and_bundle_indexes(source):
    p = nesshi.Processor(nesshi.assemble(source / "examples/dot3.s"))
    with pytest.raises(KeyError, match="data label"):
        p.break_at("vec_a")
    with pytest.raises(ValueError, match="no bundle -1"):
        p.break_at(-1)
    with pytest.raises(TypeError):
        p.break_at(2.5)
    assert p.breakpoints == set()


def test_run_is_interruptible():
    p = nesshi.Processor(nesshi.assemble(LOOP))
    threading.Timer(0.2, _thread.interrupt_main).start()
    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        p.run(max_cycles=10**11)
    assert time.monotonic() - start < 10 and p.status == "running"
    assert p.run(max_cycles=3 * 2**24 + 5) == "running"  # slices add up to the budget


def test_a_processor_running_in_another_thread_is_not_touched():
    p = nesshi.Processor(nesshi.assemble(LOOP))
    runner = threading.Thread(target=lambda: [p.run(max_cycles=2_000_000) for _ in range(100)])
    runner.start()
    refused = 0
    while runner.is_alive():
        try:
            p.reset()
            p.stats()
        except RuntimeError as e:
            assert "running in another thread" in str(e)
            refused += 1
    runner.join()
    assert refused > 0


@pytest.mark.parametrize("option, message", [
    (dict(size=0), "bad size 0x0"),
    (dict(size=(16, 0)), "bad size 16x0"),
    (dict(grid=0), "bad grid resolution 0"),
    (dict(grid="AUTO"), "grid is 'auto'"),
    (dict(quantum=0), "quantum must be an integer between 1 and 1000000"),  # hung
    (dict(pes=65), "pes must be"),
    (dict(ray_slots=0), "ray_slots must be"),
    (dict(cutoff=2.0), "cutoff must be a number between 0 and 1"),
    (dict(cache=True, cache_line=3), "cache_line must be"),
])
def test_render_options_out_of_the_commands_ranges(option, message):
    with pytest.raises(ValueError, match=message):
        nesshi.render("balls:1", **{"size": 4, "grid": 3, **option})


def test_reset_empties_the_fifo_queues(source):
    p = nesshi.Processor(nesshi.assemble(source / "examples/fifo_echo.s"))
    p.feed(0, [2, 5])
    assert p.run() == "blocked"
    p.reset()
    assert list(p.received(1)) == [] and p.cycle == 0
    p.feed(0, [1, 41])
    assert p.run() == "halted" and list(p.received(1)) == [42]


def test_pipeline_options_out_of_the_commands_ranges(source):
    for ii in (-1, 2**31 - 1):  # -1 searched as 0 did; 2**31-1 raised MemoryError
        with pytest.raises(ValueError, match="ii must be 0"):
            nesshi.pipeline(source / "examples/linear/saxpy.sa", ii=ii)
    with pytest.raises(ValueError, match="exact must be"):
        nesshi.pipeline(source / "examples/linear/saxpy.sa", exact=-1.0)


def test_step_is_interruptible_and_exact_across_slices():
    p = nesshi.Processor(nesshi.assemble(LOOP))
    assert p.step(3 * 2**22 + 7) == "running" and p.cycle == 3 * 2**22 + 7
    threading.Timer(0.2, _thread.interrupt_main).start()
    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        p.step(10**11)
    assert time.monotonic() - start < 10


def test_a_scene_file_as_a_path(tmp_path):
    nff = tmp_path / "balls.nff"
    nff.write_text(nesshi_scene_text := "v\nfrom 0 -4 0\nat 0 0 0\nup 0 0 1\nangle 40\nhither 0.01\n"
                   "resolution 8 8\nb 0 0 0\nl 2 -4 3\nf 1 0 0 1 0 0 0 0\ns 0 0 0 1\n")
    assert nesshi.scene(nff).info()["spheres"] == 1 == nesshi.scene(nesshi_scene_text).info()["spheres"]
    with pytest.raises(TypeError, match="a scene is"):
        nesshi.scene(5)


def test_a_machine_file_as_a_path(source):
    assert nesshi.machine(source / "isa/machines/ic.toml").same_as(nesshi.machine("ic"))
    with pytest.raises(TypeError, match="a machine is"):
        nesshi.machine(5)


def test_errors_and_machines_pickle_for_multiprocessing():
    import pickle
    with pytest.raises(nesshi.AssemblyError) as caught:
        nesshi.assemble("foo")
    again = pickle.loads(pickle.dumps(caught.value))
    assert type(again) is nesshi.AssemblyError and str(again) == str(caught.value) and again.line == 1
    text = nesshi.machine('inherits = "ic"\nname = "ic-f3"\n[latency]\nfmul = 3\n')
    for m in (nesshi.machine("ic-real"), text):
        assert pickle.loads(pickle.dumps(m)) == m


def test_machine_options_need_a_simulated_model():
    for option in (dict(pes=4), dict(os_machine="ic"), dict(cache=True), dict(checked=True)):
        with pytest.raises(ValueError, match="needs model S, M or V"):
            nesshi.render("balls:1", model="native", size=4, grid=3, **option)
