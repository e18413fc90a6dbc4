"""The type stubs say what the compiled module has: every function, every parameter with its
kind and default, and nothing the module lacks."""

import ast
import inspect
from pathlib import Path

import udc_studio
from udc_studio import _native

STUB = Path(udc_studio.__file__).with_name("_native.pyi")


def stub_functions():
    tree = ast.parse(STUB.read_text(encoding="utf-8"))
    return {node.name: node for node in tree.body if isinstance(node, ast.FunctionDef)}


#: A parameter without a default (distinct from a default of None).
REQUIRED = "<required>"


def parameters(node):
    args = node.args
    positional = args.posonlyargs + args.args
    defaults = [None] * (len(positional) - len(args.defaults)) + args.defaults
    out = [(a.arg, "positional", d) for a, d in zip(positional, defaults)]
    out += [(a.arg, "keyword", d) for a, d in zip(args.kwonlyargs, args.kw_defaults)]
    return [
        (name, kind, REQUIRED if d is None else ast.literal_eval(d)) for name, kind, d in out
    ]


def runtime_parameters(function):
    out = []
    for p in inspect.signature(function).parameters.values():
        kind = "keyword" if p.kind is p.KEYWORD_ONLY else "positional"
        default = REQUIRED if p.default is p.empty else p.default
        out.append((p.name, kind, default))
    return out


def test_every_native_function_has_a_stub_and_no_stub_is_stale():
    functions = {n for n in dir(_native) if callable(getattr(_native, n)) and not n.startswith("_")}
    assert functions == set(stub_functions())


def test_stub_parameters_match_the_module():
    for name, node in stub_functions().items():
        assert parameters(node) == runtime_parameters(getattr(_native, name)), name


def test_the_package_is_typed():
    assert Path(udc_studio.__file__).with_name("py.typed").is_file()
