"""Rooms a reader can hold in their head: no module of fogts over 500 lines, and every
function over 80 lines (decorators included) preceded by a comment that says why it is long.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "fogts"
MAX_MODULE_LINES = 500
MAX_FUNCTION_LINES = 80


def long_functions_without_reason(source: str) -> list[tuple[str, int]]:
    """(name, lines) of each function over ``MAX_FUNCTION_LINES`` lines with no comment
    line directly above its first line (its first decorator, if any)."""
    lines = source.splitlines()
    found = []
    for node in ast.walk(ast.parse(source)):
        if not isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            continue
        first = node.decorator_list[0].lineno if node.decorator_list else node.lineno
        length = (node.end_lineno or node.lineno) - first + 1
        above = lines[first - 2].strip() if first >= 2 else ""
        if length > MAX_FUNCTION_LINES and not above.startswith("#"):
            found.append((node.name, length))
    return found


MODULES = sorted(PACKAGE.rglob("*.py"))


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_module_is_short_and_long_functions_say_why(path: Path) -> None:
    source = path.read_text()
    assert len(source.splitlines()) <= MAX_MODULE_LINES
    assert long_functions_without_reason(source) == []


def test_the_rule_catches_a_long_function_without_a_reason() -> None:
    body = "".join(f"    x{i} = {i}\n" for i in range(MAX_FUNCTION_LINES))
    bare = f"def f():\n{body}"
    assert long_functions_without_reason(bare) == [("f", MAX_FUNCTION_LINES + 1)]
    explained = f"# Over 80 lines: one table of cases.\n@staticmethod\ndef f():\n{body}"
    assert long_functions_without_reason(explained) == []
    short = "def g():\n    return 1\n"
    assert long_functions_without_reason(short) == []
