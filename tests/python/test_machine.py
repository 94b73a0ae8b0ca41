import nesshi
import pytest

from conftest import cli


def test_presets_are_listed():
    assert set(nesshi.presets()) >= {"os", "ic", "seq", "os-real", "ic-real", "seq-real"}


def test_a_preset_as_attributes():
    m = nesshi.machine("ic-real")
    assert m.name == "ic-real"
    assert m.branch_penalty == 1
    assert m.latency["fadd"] == 3 and m.latency["fdiv"] == 12
    assert [s["name"] for s in m.slots] == ["iu0", "fpu0", "fpu1", "fpu2"]
    assert "fadd" in m.slots[1]["accepts"] and "fadd" not in m.slots[0]["accepts"]
    assert m.registers["float"] == {"count": 128, "read_ports": 7, "write_ports": 3}
    assert any(r["name"] == "resident" for r in m.memories)


def test_the_toml_text_is_the_preset_isa_prints():
    _, text, _ = cli("isa", "--machine-toml", "os")
    assert nesshi.machine(text) == nesshi.machine("os")


def test_a_copy_of_a_preset_is_the_preset():
    copy = nesshi.machine(toml='inherits = "os"\nname = "my-os"\n')
    assert copy.same_as(nesshi.machine("os"))
    assert nesshi.machine('inherits = "os"\nname = "mine"\n[latency]\nfadd = 3\n').latency["fadd"] == 3


def test_a_machine_file(tmp_path):
    f = tmp_path / "slow.toml"
    f.write_text('inherits = "ic"\nname = "slow"\n[latency]\nfmul = 4\n')
    m = nesshi.machine(str(f))
    assert (m.name, m.latency["fmul"], m.source) == ("slow", 4, str(f))


def test_a_bad_description_is_located():
    with pytest.raises(nesshi.Error) as e:
        nesshi.machine('inherits = "os"\nname = "bad"\n[latency]\nfadd = "three"\n')
    assert e.value.file == "<string>" and e.value.line == 4 and e.value.column > 0
    assert str(e.value).startswith("<string>:4:")


def test_an_unknown_preset():
    with pytest.raises(nesshi.Error, match="nosuch"):
        nesshi.machine("nosuch")
