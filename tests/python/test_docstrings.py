"""The module documents itself: every public function and property of spectralize and
spectralize.rt has a docstring that names each of its arguments (with its default where it has
one) and its cost; every option the functions take (the settings schema's keys, as `spectra()`
lists them) appears in `spectra()`'s docstring and in the guide (its Python chapter or the
command-line reference the build makes from the same schema)."""
import inspect
import os
import re

import spectralize
import spectralize.rt

SOURCE = os.path.join(os.path.dirname(__file__), "..", "..")


def public_callables():
    for module in (spectralize, spectralize.rt):
        for name, obj in vars(module).items():
            if name.startswith("_") or inspect.ismodule(obj):
                continue
            if inspect.isclass(obj):
                if issubclass(obj, Warning):
                    continue
                yield f"{module.__name__}.{name}", obj.__init__
                for member, value in vars(obj).items():
                    if not member.startswith("_"):
                        yield f"{module.__name__}.{name}.{member}", value
            elif callable(obj):
                yield f"{module.__name__}.{name}", obj


def signature_arguments(doc):
    """The argument names and defaults of a pybind11 docstring's signature lines."""
    out = {}
    for line in doc.split("\n"):
        m = re.match(r"^(?:\d+\. )?\w+\((.*)\) ->", line.strip())
        if not m:
            continue
        for part in m.group(1).split(","):
            part = part.strip()
            if not part or part in ("*", "self") or part.startswith("self:") or part.startswith("**"):
                continue
            name = part.split(":")[0].split("=")[0].strip()
            default = part.split("=", 1)[1].strip() if "=" in part else None
            out[name] = default
    return out


def test_every_public_function_names_its_arguments_defaults_and_cost():
    checked = 0
    for name, obj in public_callables():
        doc = obj.__doc__
        assert doc and doc.strip(), f"{name} has no docstring"
        assert "Cost:" in doc, f"{name}'s docstring does not state its cost"
        # pybind11's own signature line aside: the written text must name each argument.
        body = "\n".join(doc.strip().split("\n")[1:])
        for arg, default in signature_arguments(doc).items():
            assert arg in body, f"{name}'s docstring does not name its argument {arg}"
            if default not in (None, "None"):
                assert default.strip("'") in body, f"{name}: default {arg}={default} not stated"
        checked += 1
    assert checked >= 10


def options_of_spectra():
    doc = spectralize.spectra.__doc__
    block = doc.split("Options:", 1)[1]
    return re.findall(r"^\s{4}(\w+):", block, re.M)


def test_every_option_is_in_the_docstring_and_the_guide():
    options = options_of_spectra()
    assert len(options) >= 10
    guide = open(os.path.join(SOURCE, "docs", "guide", "python.md"), encoding="utf-8").read()
    for option in options:
        assert f"`{option}`" in guide, f"the guide's Python chapter does not name {option}"
        assert re.search(rf"^\s{{4}}{option}: .*\(default: ", spectralize.spectra.__doc__, re.M), (
            f"spectra()'s docstring does not give {option} with its default")
