import json

import nesshi
import numpy as np
import pytest

from conftest import cli, cli_json


def test_assemble_and_run_dot3(source):
    obj = nesshi.assemble(source / "examples/dot3.s")
    assert obj.machine == "os" and obj.bundles == 8
    p = nesshi.Processor(obj)
    assert p.run() == "halted"
    assert p.read("result")[0] == np.float32(7.0)
    assert p.reg("f10") == 7.0 and p.reg("r3") == obj.labels["result"]


def test_stats_equal_the_command_line(source):
    for engine in ("fast", "checked"):
        p = nesshi.Processor(nesshi.assemble(source / "examples/dot3.s"), engine=engine)
        p.run()
        assert p.stats() == cli_json("sim", source / "examples/dot3.s", "--engine", engine, "--stats-json", "-")


def test_disassembly_equals_nesshi_dis(source, tmp_path):
    obj = nesshi.assemble(source / "examples/dot3.s")
    obj.save(tmp_path / "dot3.o")
    status, out, _ = cli("dis", tmp_path / "dot3.o")
    assert status == 0 and nesshi.disassemble(obj) == out
    again = nesshi.assemble(nesshi.disassemble(obj), machine="os")
    assert again.to_bytes() == obj.to_bytes()


def test_memory_written_before_the_run(source):
    p = nesshi.Processor(nesshi.assemble(source / "examples/dot3.s"))
    p.write("vec_a", [1.0, 1.0, 1.0])
    p.run()
    assert p.read("result", 1)[0] == np.float32(4.0 + 0.5 + 8.0)
    assert list(p.read("vec_b", dtype="u32")) == [0x40800000, 0x3F000000, 0x41000000]
    with pytest.raises(KeyError):
        p.read("nosuch")


LOAD = """        .data 0x100
x:      .float 3.0
        .text
        li r1, x
        flw f1, 0(r1)
        nop
        nop
        halt
"""


def test_writes_in_flight():
    p = nesshi.Processor(nesshi.assemble(LOAD, machine="os-real"))  # loads take 2 cycles there
    assert p.step(2) == "running" and p.pc == 2
    assert p.inflight() == [{"reg": "f1", "value": 3.0, "lands": p.cycle + 1}]
    p.step(2)
    assert p.inflight() == [] and p.reg("f1") == 3.0


def test_step_and_breakpoints(source):
    p = nesshi.Processor(nesshi.assemble(source / "examples/dot3.s"))
    assert p.step(2) == "running" and p.pc == 2
    p.break_at(5)
    assert p.run() == "running" and p.pc == 5
    assert p.run() == "halted"
    assert p.run(max_cycles=3) == "halted"


def test_fifo_words_in_and_out(source):
    p = nesshi.Processor(nesshi.assemble(source / "examples/fifo_echo.s"))
    p.feed(0, [3, 10, 20, 30])
    assert p.run() == "halted"
    assert list(p.received(1)) == [11, 21, 31]
    with pytest.raises(KeyError):
        p.feed(7, [1])


def test_a_blocked_program_says_so(source):
    p = nesshi.Processor(nesshi.assemble(source / "examples/fifo_echo.s"))
    p.feed(0, [2, 5])
    assert p.run() == "blocked"


def test_assembly_errors_carry_their_place(source, tmp_path):
    bad = tmp_path / "bad.s"
    bad.write_text("# machine: os\n        li r1, 1\n        frob r2, r1\n        halt\n")
    with pytest.raises(nesshi.AssemblyError) as e:
        nesshi.assemble(bad)
    err = e.value
    assert (err.file, err.line, err.column) == (str(bad), 3, 9)
    status, _, stderr = cli("asm", bad, "-o", tmp_path / "bad.o")
    assert status == 1 and err.diagnostics == stderr
    assert f"{bad}:3:9: error: {err.message}" in stderr
    assert err.errors[0][:3] == (str(bad), 3, 9)


def test_loop_report(source):
    obj = nesshi.assemble(source / "examples/fifo_echo.s")
    loops = nesshi.loop_report(obj)
    assert [l["label"] for l in loops] == ["loop"]
    assert loops[0]["ii"] >= 2 and "text" in loops[0]
    _, out, _ = cli("loop", source / "examples/fifo_echo.s", "--json", "-")
    assert json.loads(out)[0]["ii"] == loops[0]["ii"]


def test_bad_arguments():
    with pytest.raises(ValueError):
        nesshi.Processor(nesshi.assemble("halt\n"), engine="turbo")
    with pytest.raises(ValueError):
        nesshi.Processor(nesshi.assemble("halt\n")).reg("x9")
