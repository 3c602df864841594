"""The public API: every name in fogts.__all__ resolves, lazily."""

from __future__ import annotations

import subprocess
import sys

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

    assert fogts.plots.plot_allan is not None  # was AttributeError without an import
    assert fogts.hygiene.detect_glitches is fogts.detect_glitches
    assert importlib.resources.files("fogts").joinpath("py.typed").is_file()
