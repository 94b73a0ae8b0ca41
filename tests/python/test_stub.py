"""The type stub the build writes beside the module (python/tools/write_stub.py): it parses, and it
names every public function, class, method and property of the module, with no name of its own."""
import ast
import os

import nesshi


def stub_tree():
    path = os.path.join(os.path.dirname(nesshi.__file__), "nesshi.pyi")
    with open(path) as f:
        return ast.parse(f.read(), path)


def test_the_stub_names_what_the_module_has():
    tree = stub_tree()
    top = {n.name: n for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    public = {n for n in dir(nesshi) if not n.startswith("_")}
    assert set(top) == public
    for name, node in top.items():
        obj = getattr(nesshi, name)
        if not isinstance(node, ast.ClassDef) or issubclass(obj, BaseException):
            continue
        in_stub = {f.name for f in node.body if isinstance(f, ast.FunctionDef) and not f.name.startswith("_")}
        in_module = {a for a in vars(obj) if not a.startswith("_")}
        assert in_stub == in_module, name


def test_signatures_carry_types():
    tree = stub_tree()
    render = next(n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name == "render")
    assert [a.arg for a in render.args.args][:3] == ["scene", "model", "size"]
    assert all(a.annotation is not None for a in render.args.args)
    machine = next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "Machine")
    name = next(f for f in machine.body if isinstance(f, ast.FunctionDef) and f.name == "name")
    assert ast.unparse(name.returns) == "str"
    error = next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "AssemblyError")
    assert "errors" in {a.target.id for a in error.body if isinstance(a, ast.AnnAssign)}
