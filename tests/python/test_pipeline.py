import nesshi
import pytest

from conftest import cli


def test_pipeline_equals_the_command_line(source):
    sa = source / "examples/linear/saxpy.sa"
    r = nesshi.pipeline(sa)
    status, out, _ = cli("pipeline", sa)
    assert status == 0 and r.code == out
    assert r.ii >= r.mii == max(r.res_mii, r.rec_mii) and r.stages >= 1
    assert r.verification.startswith("equals the sequential one")
    assert r.registers and "r9" in r.source_registers or r.source_registers


def test_pipeline_on_another_machine_and_its_loop_report(source):
    r = nesshi.pipeline(source / "examples/linear/saxpy.sa", machine=nesshi.machine("os-real"))
    assert r.code.startswith("# machine: os-real\n")
    loops = r.loop_report()
    assert loops and all("mrt" in l or "text" in l for l in loops)


def test_pipeline_at_a_given_ii(source):
    r = nesshi.pipeline(source / "examples/linear/saxpy.sa", ii=5, verify=False)
    assert r.ii == 5 and r.verification.startswith("not run")


def test_shorten_asks_the_solver_whatever_the_trip_count(source):
    sa = source / "examples/linear/livermore1.sa"
    default, shortened = nesshi.pipeline(sa), nesshi.pipeline(sa, shorten=True)
    status, out, _ = cli("pipeline", sa, "--shorten")
    assert status == 0 and shortened.code == out
    assert "not shortened by the solver" in default.code and "not shortened" not in shortened.code
    assert shortened.stages < default.stages and shortened.ii == default.ii


def test_a_bad_region_is_an_error():
    with pytest.raises(nesshi.Error) as e:
        nesshi.pipeline("        .pipeline f1\n        fadd %a, %a, f0\n        .endpipeline\n")
    assert e.value.file == "<string>" and e.value.line == 1


def test_regions_as_data_equal_the_command_line_json(source, tmp_path):
    import json

    sa = source / "examples/linear/horner.sa"  # has a .trip: the whole-run figures the choice was made by
    r = nesshi.pipeline(sa, machine="os-real")
    status, _, err = cli("pipeline", sa, "-m", "os-real", "--json", tmp_path / "r.json", "-o", tmp_path / "r.s", "-q")
    assert status == 0, err
    assert r.regions == json.loads((tmp_path / "r.json").read_text())
    assert r.regions[0]["trip"] is not None


def test_the_schedule_picture_equals_the_command_line(source, tmp_path):
    sa = source / "examples/linear/livermore1.sa"
    r = nesshi.pipeline(sa, verify=False)
    status, _, err = cli("pipeline", sa, "--no-verify", "-q", "-o", tmp_path / "l1.s", "--svg", tmp_path / "l1.svg")
    assert status == 0, err
    assert r.svgs == [(tmp_path / "l1.svg").read_text()]
    assert "iteration stage" in r.svgs[0]
