"""The public API: every name in fogts.__all__ resolves, lazily."""

from __future__ import annotations

import ast
import dataclasses
import inspect
import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

import fogts


@pytest.mark.parametrize("name", fogts.__all__)
def test_every_public_name_resolves(name: str) -> None:
    assert getattr(fogts, name) is not None


def test_unknown_name() -> None:
    with pytest.raises(AttributeError, match="module 'fogts' has no attribute 'nope'"):
        fogts.nope  # noqa: B018


def test_import_is_light() -> None:
    code = "import sys, fogts; print('statsmodels' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.strip()
    assert out == "False"


def test_submodules_are_attributes_and_the_package_is_typed() -> None:
    import importlib.resources

    assert fogts.report.plots.plot_allan is not None  # no import needed
    assert fogts.plots.plot_allan is fogts.report.plots.plot_allan
    assert fogts.preprocess.hygiene.detect_glitches is fogts.detect_glitches
    assert importlib.resources.files("fogts").joinpath("py.typed").is_file()


def test_static_imports_match_the_lazy_table() -> None:
    """The ``if TYPE_CHECKING:`` imports name each public name from the module that
    ``_EXPORTS`` loads it from, and that module defines it."""
    tree = ast.parse(Path(fogts.__file__).read_text())
    block = next(n for n in tree.body if isinstance(n, ast.If)
                 and isinstance(n.test, ast.Name) and n.test.id == "TYPE_CHECKING")
    static = {a.name: node.module for node in block.body if isinstance(node, ast.ImportFrom)
              for a in node.names if node.module and node.module != "fogts"
              and f"{node.module}.{a.name}" not in fogts._SUBMODULES.values()}
    assert static == fogts._EXPORTS
    defined_elsewhere = {name: module for name, module in fogts._EXPORTS.items()
                         if getattr(getattr(fogts, name), "__module__", module) != module}
    assert not defined_elsewhere


# --- the API surface -------------------------------------------------------------------

API_FIXTURE = Path(__file__).resolve().parent / "golden" / "api.json"


def _signature(obj: object) -> str:
    try:
        text = str(inspect.signature(obj))  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return "<no signature>"
    return re.sub(r" at 0x[0-9a-f]+>", ">", text)  # default functions: no address


def api_surface() -> dict[str, dict[str, str]]:
    """Every public name: its signature and, for classes, the signatures of its public
    methods and properties (the names a user's code can touch)."""
    surface: dict[str, dict[str, str]] = {}
    for name in sorted(fogts.__all__):
        obj = getattr(fogts, name)
        if name == "__version__":
            continue
        entry = {"": _signature(obj)} if callable(obj) else {"": type(obj).__name__}
        if inspect.isclass(obj):
            for attr, member in sorted(vars(obj).items()):
                if attr.startswith("_") and attr not in ("__init__", "__call__"):
                    continue
                if isinstance(member, property):
                    entry[attr] = "property"
                elif isinstance(member, (staticmethod, classmethod)):
                    entry[attr] = _signature(member.__func__)
                elif callable(member):
                    entry[attr] = _signature(member)
            if dataclasses.is_dataclass(obj):
                entry["<fields>"] = ", ".join(f.name for f in dataclasses.fields(obj))
        surface[name] = entry
    return surface


def test_the_api_surface_is_unchanged() -> None:
    """Names, signatures, result fields and methods equal the fixture; after an intended
    change regenerate it with ``python -m tests.test_public_api``."""
    expected = json.loads(API_FIXTURE.read_text())
    actual = api_surface()
    assert sorted(expected) == sorted(actual), "public names differ"
    for name in expected:
        assert expected[name] == actual[name], f"{name} changed"


if __name__ == "__main__":  # pragma: no cover - maintenance entry point
    API_FIXTURE.write_text(json.dumps(api_surface(), indent=1) + "\n")
    print(f"wrote {API_FIXTURE}", file=sys.stderr)
