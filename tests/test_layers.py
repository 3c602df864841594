"""Data flows one way: no module of fogts imports a module of a higher layer.

Layers, lowest first: the leaf modules (errors, choices, units, tables, _typing, _validate,
_version, progress) ->
io -> preprocess -> allan, arma -> startup -> simulate -> pipeline -> report -> batch ->
cli (the simulator draws thermal drift from the start-up domain's thermal model).  The package facade ``fogts/__init__.py`` (lazy re-exports) and ``__main__`` are
above everything.  Imports under ``if TYPE_CHECKING:`` count too: a type a lower layer
needs from a higher one means the code is in the wrong place.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "fogts"

LAYERS: dict[str, int] = {
    "errors": 0, "choices": 0, "units": 0, "tables": 0, "_typing": 0, "_validate": 0, "_version": 0,
    "progress": 0,
    "io": 1, "preprocess": 2, "allan": 3, "arma": 3, "startup": 4, "simulate": 5,
    "pipeline": 6, "report": 7, "batch": 8, "cli": 9, "__main__": 10, "__init__": 10,
}


def _top(module: str) -> str:
    """``fogts.allan.noise`` -> ``allan``."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


def _module_of(path: Path) -> str:
    rel = path.relative_to(PACKAGE.parent).with_suffix("")
    return ".".join(rel.parts)


def _imports(path: Path) -> list[tuple[int, str]]:
    tree = ast.parse(path.read_text(), filename=str(path))
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
            found += [(node.lineno, n) for n in names if n.split(".")[0] == "fogts"][:1]
        elif isinstance(node, ast.Import):
            found += [(node.lineno, a.name) for a in node.names
                      if a.name.split(".")[0] == "fogts"]
    return found


MODULES = sorted(p for p in PACKAGE.rglob("*.py"))


def test_every_top_level_name_has_a_layer() -> None:
    tops = {_top(_module_of(p)) for p in MODULES}
    assert tops <= set(LAYERS), f"add to LAYERS: {sorted(tops - set(LAYERS))}"


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_no_upward_import(path: Path) -> None:
    here = _top(_module_of(path))
    upward = [f"line {line}: {name}" for line, name in _imports(path)
              if name != "fogts" and LAYERS.get(_top(name), 99) > LAYERS[here]]
    assert not upward, f"{path.relative_to(PACKAGE)} ({here}) imports upward: {upward}"


def test_the_rule_catches_an_upward_import(tmp_path: Path) -> None:
    """The check itself: an import of the cli from io is found."""
    bad = tmp_path / "bad.py"
    bad.write_text("from fogts.cli._common import app\n")
    assert [n for _, n in _imports(bad) if LAYERS[_top(n)] > LAYERS["io"]]
