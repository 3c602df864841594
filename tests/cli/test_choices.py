"""The CLI's choice Enums carry exactly the library's choices, and typer validates them."""

from __future__ import annotations

from enum import StrEnum

import pytest
from typer.testing import CliRunner

from fogts.allan.taus import KINDS
from fogts.cli import app
from fogts.cli._common import (
    Criterion,
    Estimator,
    FilterDesign,
    FlickerMethod,
    GapPolicy,
    NanPolicy,
    NoiseFitMethod,
)
from fogts.io.reader import NAN_POLICIES
from fogts.preprocess.filters import FILTER_DESIGNS
from fogts.preprocess.hygiene import GAP_POLICIES
from fogts.simulate.streams import FLICKER_METHODS


@pytest.mark.parametrize(("enum", "library"), [
    (Estimator, KINDS), (NanPolicy, NAN_POLICIES), (GapPolicy, GAP_POLICIES),
    (Criterion, ("aic", "bic", "hqic", "aicc")), (NoiseFitMethod, ("wls", "gls", "ols")),
    (FilterDesign, FILTER_DESIGNS), (FlickerMethod, FLICKER_METHODS),
])
def test_enum_values_are_the_library_choices(enum: type[StrEnum], library: tuple[str, ...]
                                             ) -> None:
    assert sorted(e.value for e in enum) == sorted(library)


@pytest.mark.parametrize(("command", "option"), [
    ("allan", "--kind"), ("allan", "--method"), ("select", "--criterion"),
    ("davar", "--kind"), ("info", "--nan"), ("allan", "--gaps"), ("batch", "--criterion"),
])
def test_a_bad_choice_is_one_error_line_naming_the_option(
        command: str, option: str, capsys: pytest.CaptureFixture[str]) -> None:
    from fogts.cli import main

    with pytest.raises(SystemExit) as exit_info:
        main([command, "data/example_fog_10hz_3h.csv", option, "nope"])
    assert exit_info.value.code == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: Invalid value for '" + option + "'") and "'nope'" in err
    assert "\n" not in err and "Traceback" not in err


def test_help_lists_the_choices() -> None:
    res = CliRunner().invoke(app, ["select", "--help"], env={"COLUMNS": "200"})
    assert "aic|bic|hqic|aicc" in res.stdout
