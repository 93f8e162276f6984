"""The type stub (python/aniso/__init__.pyi) is what python/tools/make_stub.py writes, and lists
every public name of the module, every method and property of its classes, and their keywords."""
import ast
import inspect
import pathlib
import subprocess
import sys

import aniso
from conftest import SOURCE_DIR

STUB = SOURCE_DIR / "python" / "aniso" / "__init__.pyi"


def stub_tree():
    return ast.parse(STUB.read_text())


def test_stub_is_up_to_date():
    tool = SOURCE_DIR / "python" / "tools" / "make_stub.py"
    p = subprocess.run([sys.executable, str(tool), "--check"], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr


def test_stub_lists_what_the_module_has():
    tree = stub_tree()
    top = {n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    top |= {t.id for n in tree.body if isinstance(n, ast.AnnAssign) for t in [n.target]}
    public = {n for n in dir(aniso) if not n.startswith("_") and not inspect.ismodule(getattr(aniso, n))}
    assert set(aniso.__all__) <= top
    assert public - {"annotations"} <= top | {"__version__"}, public - top
    classes = {n.name: n for n in tree.body if isinstance(n, ast.ClassDef)}
    for cls in (aniso.Material, aniso.Frame):
        members = {n.name for n in classes[cls.__name__].body if isinstance(n, ast.FunctionDef)}
        has = {n for n in dir(cls) if not n.startswith("_")}
        assert has <= members, has - members


def test_stub_keywords_are_the_json_keys():
    tree = stub_tree()
    funcs = {n.name: n for n in tree.body if isinstance(n, ast.FunctionDef)}
    for spec in aniso.models().values():
        f = funcs[spec["name"].replace("-", "_")]
        assert [a.arg for a in f.args.kwonlyargs] == [p["name"] for p in spec["params"]]
