"""The type stubs and docstrings: editors and help() see the API as it is. The native module's
stub (_cutdyn.pyi) names every function with the parameters and defaults pybind11 reports for
it; every public function of the package is annotated and documented."""

import ast
import inspect
import os

import cutdyn
import cutdyn.monitor
from cutdyn import _cutdyn

PACKAGE = os.path.dirname(cutdyn.__file__)


def top_level_split(text):
    """Splits "a: X[int, str] = 1, b: str = ','" at the commas between parameters."""
    parts, depth, quote, start = [], 0, None, 0
    for i, ch in enumerate(text):
        if quote:
            quote = None if ch == quote else quote
        elif ch in "'\"":
            quote = ch
        elif ch in "[(":
            depth += 1
        elif ch in "])":
            depth -= 1
        elif ch == "," and depth == 0:
            parts.append(text[start:i].strip())
            start = i + 1
    if text[start:].strip():
        parts.append(text[start:].strip())
    return parts


def native_parameters(function):
    """[(name, default or the string "required")] from pybind11's signature line."""
    line = function.__doc__.strip().splitlines()[0]
    inside = line[line.index("(") + 1:line.rindex(")")]
    out = []
    for p in top_level_split(inside):
        name = p.split(":")[0].strip()
        default = ast.literal_eval(p.split("=", 1)[1].strip()) if "=" in p else "required"
        out.append((name, default))
    return out


def stub_functions():
    tree = ast.parse(open(os.path.join(PACKAGE, "_cutdyn.pyi")).read())
    out = {}
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            args = node.args.args
            defaults = [None] * (len(args) - len(node.args.defaults)) + node.args.defaults
            out[node.name] = [(a.arg, "required" if d is None else ast.literal_eval(d))
                              for a, d in zip(args, defaults)]
    return out


def test_the_native_stub_is_the_module():
    stubs = stub_functions()
    native = {name for name in dir(_cutdyn) if not name.startswith("_")
              and inspect.isbuiltin(getattr(_cutdyn, name))}
    assert set(stubs) == native
    for name in native:
        assert stubs[name] == native_parameters(getattr(_cutdyn, name)), name


def test_every_public_function_is_annotated_and_documented():
    for module in (cutdyn, cutdyn.monitor):
        for name in module.__all__:
            obj = getattr(module, name)
            if inspect.isfunction(obj):
                assert obj.__doc__ and len(obj.__doc__) > 40, name
                signature = inspect.signature(obj)
                assert signature.return_annotation is not inspect.Signature.empty, name
                for p in signature.parameters.values():
                    assert p.annotation is not inspect.Parameter.empty, (name, p.name)
            elif inspect.isclass(obj):
                assert obj.__doc__, name
    assert os.path.exists(os.path.join(PACKAGE, "py.typed"))


def test_help_shows_the_api():
    text = __import__("pydoc").render_doc(cutdyn.lobes)
    assert "target_depth_mm" in text and "cutdyn lobes" in text
    text = __import__("pydoc").render_doc(cutdyn.monitor.estimate)
    assert "bandwidth_hz" in text and "monitor estimate" in text
