import contextlib
import io
import os
import re


def test_the_readme_python_block_runs(source):
    """Each print( line's comment is what it prints, `...` standing for any text."""
    blocks = re.findall(r"```python\n(.*?)```", (source / "README.md").read_text(), re.S)
    assert blocks, "the README shows no Python"
    out = io.StringIO()
    cwd = os.getcwd()
    os.chdir(source)  # its paths are the checkout's
    try:
        with contextlib.redirect_stdout(out):
            for b in blocks:
                exec(compile(b, "README.md", "exec"), {})
    finally:
        os.chdir(cwd)
    want = [l.split("# ", 1)[1] for b in blocks for l in b.splitlines() if l.startswith("print(")]
    got = out.getvalue().splitlines()
    assert len(got) == len(want)
    for w, g in zip(want, got):
        assert re.fullmatch(".*".join(map(re.escape, w.strip().split("..."))), g.strip()), (w, g)
