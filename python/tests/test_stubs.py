"""The type stubs (pmu50/_native.pyi) describe the module as it is, and everything is documented."""

from __future__ import annotations

import ast
import inspect
import re
from pathlib import Path

import pmu50
from pmu50 import _native

STUB = Path(pmu50.__file__).with_name("_native.pyi")
PRIVATE_STUB = {
    "_Values",
    "_Bit",
    "_Config",
    "_Inputs",
    "SignalKind",
}  # typing helpers of the stub only
PRIVATE_RUNTIME = {"_panic_for_test"}  # test hook (tests/test_errors.py)


def stub_tree() -> ast.Module:
    assert STUB.exists(), f"{STUB} is not installed with the package"
    assert STUB.with_name("py.typed").exists()
    return ast.parse(STUB.read_text())


def top_level(tree: ast.Module) -> dict[str, ast.AST]:
    out: dict[str, ast.AST] = {}
    for node in tree.body:
        if isinstance(node, (ast.ClassDef, ast.FunctionDef)):
            out[node.name] = node
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            out[node.target.id] = node
        elif isinstance(node, ast.Assign):
            for t in node.targets:
                if isinstance(t, ast.Name):
                    out[t.id] = node
    return out


def members(cls: ast.ClassDef) -> tuple[list[str], list[str]]:
    """(methods and properties, annotated attributes) of a stub class."""
    funcs = [n.name for n in cls.body if isinstance(n, ast.FunctionDef)]
    attrs = [
        n.target.id
        for n in cls.body
        if isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name)
    ]
    return funcs, attrs


def test_stub_names_are_the_modules():
    stub = set(top_level(stub_tree())) - PRIVATE_STUB
    runtime = {
        n for n in dir(_native) if not n.startswith("__") or n == "__version__"
    } - PRIVATE_RUNTIME
    assert stub == runtime
    assert set(pmu50.__all__) == runtime


def test_stub_classes_match_the_runtime_classes():
    tree = top_level(stub_tree())
    for name, node in tree.items():
        if not isinstance(node, ast.ClassDef) or name in PRIVATE_STUB:
            continue
        cls = getattr(_native, name)
        funcs, attrs = members(node)
        if issubclass(cls, BaseException):
            continue
        for f in funcs:
            if f != "__init__":
                assert hasattr(cls, f), f"{name}.{f} is in the stub but not in the module"
        if name in ("Outputs", "Internals", "InputValues"):
            continue  # dynamic attributes: checked against the signal table below
        for a in attrs:
            assert hasattr(cls, a), f"{name}.{a} is in the stub but not in the module"
        runtime = {n for n in dir(cls) if not n.startswith("_")}
        assert runtime <= set(funcs) | set(attrs), (
            f"{name}: undocumented in the stub: {runtime - set(funcs) - set(attrs)}"
        )


def test_signal_attributes_in_the_stub_are_the_table():
    tree = top_level(stub_tree())
    t = pmu50.Core().step_traced()
    for cls, values in (
        ("Outputs", t.after),
        ("Internals", t.internals),
        ("InputValues", t.inputs),
    ):
        _, attrs = members(tree[cls])
        assert attrs == values.names(), cls


def typed_dict_fields(cls: ast.ClassDef) -> dict[str, str | None]:
    """{field: its docstring or None} of a TypedDict of the stub, in order."""
    out: dict[str, str | None] = {}
    for i, n in enumerate(cls.body):
        if isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name):
            nxt = cls.body[i + 1] if i + 1 < len(cls.body) else None
            doc = (
                nxt.value.value
                if isinstance(nxt, ast.Expr) and isinstance(nxt.value, ast.Constant)
                else None
            )
            out[n.target.id] = doc
    return out


def kwargs_type(fn: ast.FunctionDef) -> str:
    """The ``Unpack[...]`` type of a function's ``**kwargs``, as source text."""
    assert fn.args.kwarg is not None and not fn.args.kwonlyargs, (
        f"{fn.name}: expected **kwargs only"
    )
    return ast.unparse(fn.args.kwarg.annotation)


def test_keyword_arguments_in_the_stub():
    tree = top_level(stub_tree())
    core = {n.name: n for n in tree["Core"].body if isinstance(n, ast.FunctionDef)}
    cov = {n.name: n for n in tree["Coverage"].body if isinstance(n, ast.FunctionDef)}
    # Core() and Coverage() take the [core] table, every step the inputs, typed once each
    for fn in (core["__init__"], cov["__init__"]):
        assert kwargs_type(fn) == "Unpack[_Config]"
    for fn in (core["step"], core["step_traced"], cov["step"], cov["step_traced"]):
        assert kwargs_type(fn) == "Unpack[_Inputs]"
    config = typed_dict_fields(tree["_Config"])
    assert list(config) == pmu50.CORE_PARAMETERS
    # the defaults the stub names are the model's
    defaults = {}
    for name, doc in config.items():
        m = re.search(r"Default ``(.+?)``\.", doc or "")
        assert m, f"_Config.{name}: no 'Default ``VALUE``.' in its docstring"
        defaults[name] = ast.literal_eval(m.group(1))
    assert defaults == pmu50.Core().config
    inputs = [s.name for s in pmu50.signal_table("input")]
    assert list(typed_dict_fields(tree["_Inputs"])) == inputs
    # an input left out is 0, as the stub says
    assert pmu50.Core().step() == pmu50.Core().step(**dict.fromkeys(inputs, 0))


def test_everything_public_has_a_docstring():
    assert pmu50.__doc__ and "Core" in pmu50.__doc__
    for name in pmu50.__all__:
        obj = getattr(pmu50, name)
        if inspect.isclass(obj) or callable(obj):
            assert (obj.__doc__ or "").strip(), f"{name} has no docstring"
    for cls in (pmu50.Core, pmu50.Scenario):
        for name, member in vars(cls).items():
            if not name.startswith("_"):
                assert (getattr(member, "__doc__", None) or "").strip(), (
                    f"{cls.__name__}.{name} has no docstring"
                )
