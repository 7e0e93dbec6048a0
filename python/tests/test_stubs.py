"""python/fcl_rs.pyi names what the module has: the same public classes, functions, methods, properties and
attributes, and each function's parameters in the module's order (pybind11 writes them into the docstring)."""
import ast
import os
import re

import fcl_rs
from conftest import SOURCE_DIR

STUB = os.path.join(SOURCE_DIR, "python", "fcl_rs.pyi")
# Type aliases of the stub, not part of the module.
ALIASES = {"ArrayLike", "BodyPair"}


def stub_members(node):
    """{name: parameter names or None (an attribute or property)} of a class body or module."""
    members = {}
    for item in node.body:
        if isinstance(item, ast.FunctionDef):
            is_property = any(isinstance(d, ast.Name) and d.id == "property" for d in item.decorator_list)
            params = [a.arg for a in item.args.args if a.arg != "self"]
            members[item.name] = None if is_property else params
        elif isinstance(item, ast.AnnAssign):
            members[item.target.id] = None
        elif isinstance(item, ast.ClassDef):
            members[item.name] = item
    return members


def runtime_params(function, name):
    """The parameter names pybind11 wrote into the first line of the docstring: name(self: T, a: X, b: Y = 1)."""
    first = (function.__doc__ or "").lstrip().splitlines()[0]
    match = re.match(rf"{re.escape(name)}\((.*)\) ->", first)
    assert match, f"{name}: no signature in {first!r}"
    return [p for p in re.findall(r"(?:^|, )(\w+):", match.group(1)) if p != "self"]


def public(obj):
    return {n for n in dir(obj) if not n.startswith("_")}


def test_stub_matches_module():
    with open(STUB) as f:
        tree = ast.parse(f.read())
    top = stub_members(tree)
    aliases = {t.id for node in tree.body if isinstance(node, ast.Assign) for t in node.targets}
    assert aliases == ALIASES
    assert set(top) - {"__version__"} == public(fcl_rs)
    for name, member in top.items():
        runtime = getattr(fcl_rs, name)
        if isinstance(member, ast.ClassDef):
            methods = stub_members(member)
            expected = public(runtime) | ({"__init__"} if "__init__" in methods else set())
            expected |= {"__contains__"} & set(methods)
            assert set(methods) == expected, name
            for method, params in methods.items():
                if params is not None:
                    assert params == runtime_params(getattr(runtime, method), method), f"{name}.{method}"
        elif member is not None:
            assert member == runtime_params(runtime, name), name
