"""The CLI's choices are the library's Literal types, and typer validates and lists them."""

from __future__ import annotations

import typing

import pytest
from typer.testing import CliRunner

from fogts import choices
from fogts.allan.noise_lsq import FIT_METHODS
from fogts.allan.taus import KINDS
from fogts.arma.select import CRITERIA
from fogts.cli import app
from fogts.io.missing import NAN_POLICIES
from fogts.preprocess.filters import FILTER_DESIGNS
from fogts.preprocess.hygiene import GAP_POLICIES
from fogts.simulate.streams import FLICKER_METHODS


@pytest.mark.parametrize(("library", "name"), [
    (KINDS, "KINDS"), (FIT_METHODS, "FIT_METHODS"), (CRITERIA, "CRITERIA"),
    (NAN_POLICIES, "NAN_POLICIES"), (GAP_POLICIES, "GAP_POLICIES"),
    (FILTER_DESIGNS, "FILTER_DESIGNS"), (FLICKER_METHODS, "FLICKER_METHODS"),
])
def test_the_domain_modules_check_against_the_one_definition(library: tuple[str, ...],
                                                             name: str) -> None:
    assert library is getattr(choices, name)


@pytest.mark.parametrize(("literal", "values"), [
    (choices.Kind, choices.KINDS), (choices.FitMethod, choices.FIT_METHODS),
    (choices.Criterion, choices.CRITERIA), (choices.NanPolicy, choices.NAN_POLICIES),
    (choices.GapPolicy, choices.GAP_POLICIES), (choices.FilterMethod, choices.FILTER_METHODS),
    (choices.FilterDesign, choices.FILTER_DESIGNS),
    (choices.FlickerMethod, choices.FLICKER_METHODS),
])
def test_each_tuple_lists_its_literal(literal: object, values: tuple[str, ...]) -> None:
    assert typing.get_args(literal) == values


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


@pytest.mark.parametrize(("command", "values"), [
    (["select"], choices.CRITERIA), (["allan"], choices.KINDS), (["allan"], choices.FIT_METHODS),
    (["info"], choices.NAN_POLICIES), (["allan"], choices.GAP_POLICIES),
    (["filter"], choices.FILTER_METHODS), (["filter"], choices.FILTER_DESIGNS),
    (["simulate", "noise"], choices.FLICKER_METHODS),
])
def test_help_lists_the_choices(command: list[str], values: tuple[str, ...]) -> None:
    res = CliRunner().invoke(app, [*command, "--help"], env={"COLUMNS": "200"})
    assert "|".join(values) in res.stdout
