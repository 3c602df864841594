"""Errors name what the user typed: the option on the command line (``--fs``), the argument
in Python (``fs_hz=``).

The library's messages name its keyword (``pass fs_hz=``, ``nan='drop'``, ``give
n_samples=N``); the command line's error guard turns each into the option
(:func:`fogts.cli._arguments.option_names`).  Before, the messages named both ("pass
fs_hz= (CLI --fs)"), or the CLI's option alone in Python ("give --n-samples N"), and a
command's own mapping turned "(n_samples=, ...)" into "(--n-samples=, ...)".  Each case
below is one message, raised once from the command line (exit 2, one ``error:`` line,
naming the option and not the argument) and once from Python (naming the argument and no
option).
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

import fogts
from fogts.allan.curve_input import read_curves
from fogts.cli import app
from fogts.cli._arguments import option_names
from fogts.errors import DataError
from tests.conftest import error_output

runner = CliRunner()


def _text(name: str, body: str) -> Callable[[Path], Path]:
    def write(folder: Path) -> Path:
        path = folder / name
        path.write_text(body)
        return path
    return write


def _burst_free_gap(folder: Path) -> Path:
    """A 10 Hz record with one 1 s gap."""
    t = np.r_[np.arange(600) / 10.0, 61.0 + np.arange(600) / 10.0]
    path = folder / "gap.csv"
    pd.DataFrame({"time": t, "rate_deg_h": np.random.default_rng(1).normal(size=t.size)}
                 ).to_csv(path, index=False)
    return path


def _clumped(folder: Path) -> Path:
    """Two stamps 0.02 s apart in a 10 Hz record with a gap: both round to one grid point."""
    t = np.r_[np.arange(300) / 10.0, 40.0 + np.arange(300) / 10.0]
    t[10] = t[9] + 0.02
    path = folder / "clumps.csv"
    pd.DataFrame({"time": t, "rate_deg_h": np.random.default_rng(2).normal(size=t.size)}
                 ).to_csv(path, index=False)
    return path


def _read(**kwargs: Any) -> Callable[[Path], Any]:
    return lambda path: fogts.read_run(path, **kwargs)


def _curve(**kwargs: Any) -> Callable[[Path], Any]:
    return lambda path: read_curves(path, **{"units": "deg/h", **kwargs})


def _gaps(policy: str) -> Callable[[Path], Any]:
    from fogts.preprocess.hygiene import assess_run

    return lambda path: assess_run(fogts.read_run(path), gaps=policy)


def _gaps_nan(path: Path) -> Any:
    from fogts.preprocess.gaps import fill_gaps_nan

    return fill_gaps_nan(fogts.read_run(path))


def _gmwm_on_a_curve(path: Path) -> Any:
    from fogts.allan.curve_input import check_curve_methods

    return check_curve_methods(["gmwm"], read_curves(path, units="deg/h").provenance)


def _too_few_taus(path: Path) -> Any:
    return fogts.fit_noise(fogts.allan_deviation(fogts.read_run(path)))


def _curve_of_a_record(path: Path) -> Any:
    from fogts.pipeline import analyse_allan_axis

    return analyse_allan_axis(fogts.read_run(path), 0)


def _select_array(path: Path) -> Any:
    return fogts.select_arma(pd.read_csv(path)["rate"].to_numpy())


def _arma_model(path: Path) -> Any:
    from fogts.startup.startup_workflow import startup_compensation

    return startup_compensation(fogts.read_run(path), arma_model="AR(9)")


def _ml_over_a_range(path: Path) -> Any:
    from fogts.pipeline import AllanSettings, analyse_allan_axis

    return analyse_allan_axis(fogts.read_run(path), 0,
                              AllanSettings(method="ml", fit_tau_min=1.0))


_NOTIME = _text("notime.csv", "rate\n1\n2\n3\n")
_TWO_COLUMNS = _text("two.csv", "time,a,b\n0,1,2\n0.1,2,3\n0.2,3,4\n")
_EMPTY_CELL = _text("empty.csv", "time,rate\n0,1\n0.1,\n0.2,3\n")
_NAN_CELL = _text("nan.csv", "time,rate\n0,1\n0.1,inf\n0.2,3\n")
_EMPTY_TIME = _text("notime_cell.csv", "time,rate\n0,1\n,2\n0.2,3\n0.3,4\n")
_MIXED = _text("mixed.csv", "time,dtheta_x,gyro_y\n0,1,2\n0.1,2,3\n0.2,3,4\n")
_NO_WEIGHTS = _text("c.csv", "tau,adev\n0.01,1\n0.02,0.7\n")
_EDF_ONLY = _text("c.csv", "tau,adev,edf\n0.01,1,90\n0.02,0.7,45\n0.04,0.5,20\n"
                           "0.08,0.36,10\n0.16,0.3,5\n0.32,0.28,3\n")
_OFF_GRID = _text("c.csv", "tau,adev,edf\n0.01,1,9\n0.025,1,9\n")
_M_COLUMN = _text("c.csv", "tau,m,adev,edf\n0.01,1,1,9\n0.02,2,1,9\n")
_SHORT = _text("short.csv", "time,rate\n" + "".join(f"{i / 10},{(-1) ** i}\n"
                                                    for i in range(40)))
_WARM = _text("warm.csv", "time,rate,temperature\n" + "".join(
    f"{i},{(-1) ** i},{20 + i / 100}\n" for i in range(200)))
_RECORD = _text("r.csv", "time,rate\n" + "".join(
    f"{i / 10},{v:.6f}\n" for i, v in enumerate(np.random.default_rng(3).normal(size=3000))))

#: (file, command line after the file, what the CLI error says, Python call, what it says)
CASES: dict[str, tuple[Callable[[Path], Path], list[str], str, Callable[[Path], Any], str]] = {
    "fs": (_NOTIME, ["info"], "no sample rate given; pass --fs or add a time column",
           _read(), "no sample rate given; pass fs_hz= or add a time column"),
    "rate column": (_TWO_COLUMNS, ["info"], "cannot tell which column is the rate; columns "
                    "are: time, a, b; pass --rate-column", _read(),
                    "columns are: time, a, b; pass rate_column="),
    "empty cell": (_EMPTY_CELL, ["info"], "has an empty cell at data row 1 (line 3 of "
                   "{path}); pass --nan drop or --nan interpolate", _read(),
                   "pass nan='drop' or nan='interpolate'"),
    "non-finite cell": (_NAN_CELL, ["info"], "fogts never drops rows silently: pass --nan "
                        "drop or --nan interpolate", _read(),
                        "never drops rows silently: pass nan='drop' or nan='interpolate'"),
    "time stamp": (_EMPTY_TIME, ["info", "--nan", "interpolate"], "time stamps are never "
                   "interpolated: pass --nan drop", _read(nan="interpolate"),
                   "time stamps are never interpolated: pass nan='drop'"),
    "input kind": (_MIXED, ["info"], "mix increment, rate; read them separately or pass "
                   "--input", _read(), "read them separately or pass input="),
    "gaps error": (_burst_free_gap, ["allan", "--gaps", "error"], "; --gaps error refuses "
                   "it: pass --gaps split to analyse the longest regular segment or --gaps "
                   "warn", _gaps("error"), "; gaps='error' refuses it: pass gaps='split' to "
                   "analyse the longest regular segment or gaps='warn'"),
    "gaps nan": (_clumped, ["allan", "--gaps", "nan"], "clumps.csv: --gaps nan puts each "
                 "sample at its nearest grid point", _gaps_nan,
                 "clumps.csv: gaps='nan' puts each sample at its nearest grid point"),
    "taus and terms": (_SHORT, ["allan"], "; use more taus (--taus) or "
                       "fewer terms (--terms), or a longer record", _too_few_taus,
                       "; use more taus (taus=) or fewer terms (terms=), or a longer record"),
    "n_samples": (_NO_WEIGHTS, ["curve", "--units", "deg/h"], "length to compute them: give "
                  "--n-samples N (the number of rate samples", _curve(),
                  "length to compute them: give n_samples=N (the number of rate samples"),
    "n_samples short": (_NO_WEIGHTS, ["curve", "--units", "deg/h", "--n-samples", "3"],
                        "--n-samples = 3 is too short for this curve", _curve(n_samples=3),
                        "give the record's own n_samples=N"),
    "n_samples gmwm": (_EDF_ONLY, ["curve", "--units", "deg/h", "--method", "gmwm"],
                       "this curve does not state it: give --n-samples N, or fit with wls",
                       _gmwm_on_a_curve,
                       "this curve does not state it: give n_samples=N, or fit with wls"),
    "channel": (_EDF_ONLY, ["curve", "--units", "deg/h", "--channel", "x"], "has no channel "
                "column (one curve); leave out --channel", _curve(channel="x"),
                "has no channel column (one curve); leave out channel="),
    "fs of a curve": (_OFF_GRID, ["curve", "--units", "deg/h", "--fs", "100"], "taus must be "
                      "m / fs with m = 1, 2, ...: give the record's --fs, or round",
                      _curve(fs_hz=100.0), "m = 1, 2, ...: give the record's fs_hz=, or round"),
    "fs of an m column": (_M_COLUMN, ["curve", "--units", "deg/h", "--fs", "200"], "give the "
                          "record's --fs (100 Hz by the file)", _curve(fs_hz=200.0),
                          "give the record's fs_hz= (100 Hz by the file)"),
    "fs alone": (_NOTIME, ["info", "--fs", "-5"], "error: --fs must be a finite number > 0, "
                 "got -5.0", _read(fs_hz=-5), "fs_hz must be a finite number > 0, got -5"),
    "curve of a record": (_SHORT, ["allan"], "error: the Allan curve of axis 'rate' of {path} "
                          "has 1 usable tau (0.1 s)", _curve_of_a_record,
                          "the Allan curve of axis 'rate' of "),
    "select input": (_SHORT, ["select"], "error: axis 'rate' of {path} is too short for ARMA "
                     "selection: 40 samples", _select_array,
                     "x is too short for ARMA selection: 40 samples"),
    "arma model": (_WARM, ["compensate", "--arma-model", "AR(9)"], "error: --arma-model must "
                   "be one of auto, AR(1), AR(2), AR(3), ARMA(1,1), ARMA(2,1); got 'AR(9)'",
                   _arma_model, "arma_model must be one of auto, AR(1), AR(2), AR(3), "
                   "ARMA(1,1), ARMA(2,1); got 'AR(9)'"),
    "fit range and ml": (_RECORD, ["allan", "--method", "ml", "--fit-tau-min", "1"],
                         "--fit-tau-min/--fit-tau-max do not apply to --method 'ml'",
                         _ml_over_a_range,
                         "fit_tau_min/fit_tau_max do not apply to method 'ml'"),
}


#: A library keyword as the messages give it (what the CLI must not show).
_KEYWORD = re.compile(r"(?<![\w.-])(fs_hz|rate_column|nan|gaps|input|n_samples|taus|terms|"
                      r"channel)=|fit_tau_m")
#: A library argument standing alone (``fs_hz must be ...``), which the CLI must not show
#: either: the shared identifiers, and those of the cases above.
_BARE = re.compile(r"(?<![\w'.-])(fs_hz|n_samples|rate_column|time_column|temperature_column|"
                   r"arma_model|allan_result)(?![\w'])")


@pytest.mark.parametrize("case", sorted(CASES))
def test_the_cli_error_names_the_option(case: str, tmp_path: Path) -> None:
    write, args, says, _, _ = CASES[case]
    path = write(tmp_path)
    res = runner.invoke(app, [args[0], str(path), *args[1:]])
    assert res.exit_code == 2, res.output
    lines = error_output(res.stderr).splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), res.stderr
    assert says.format(path=path) in lines[0]
    assert "CLI" not in lines[0] and not _KEYWORD.search(lines[0])
    assert not _BARE.search(lines[0])


@pytest.mark.parametrize("case", sorted(CASES))
def test_the_python_error_names_the_argument(case: str, tmp_path: Path) -> None:
    write, _, _, call, says = CASES[case]
    path = write(tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # assumed units, gaps: the CLI prints them apart
        with pytest.raises(DataError) as info:
            call(path)
    message = str(info.value)
    assert says in message
    assert "CLI" not in message and " --" not in message and "(--" not in message


def test_keywords_become_options_and_other_words_stay() -> None:
    assert option_names("give n_samples=N (the number)", {}) == "give --n-samples N (the number)"
    assert option_names("gaps='split' or gaps='warn'", {}) == "--gaps split or --gaps warn"
    # not a keyword the user passes: a call written out, an attribute, a bare word
    assert option_names("read_run(..., input=...)", {}) == "read_run(..., input=...)"
    assert option_names("run.fs_hz=10 and the taus", {}) == "run.fs_hz=10 and the taus"
    # a command's own names, also as whole words
    assert option_names("fit_tau_min/fit_tau_max do not apply",
                        {"fit_tau_min": "--fit-tau-min", "fit_tau_max": "--fit-tau-max"}) \
        == "--fit-tau-min/--fit-tau-max do not apply"


def test_warnings_and_json_messages_name_the_options_and_nothing_else_changes() -> None:
    """Warnings, notes and the JSON's messages: ``name=`` forms only (a bare word may be a
    column or a quantity), and in the JSON only the strings under its message keys."""
    from fogts.cli._arguments import cli_payload, option_keywords

    assert option_keywords("pass units= (deg/h); give kind=; give fs_hz= if faster") == \
        "pass --units (deg/h); give --kind; give --fs if faster"
    assert option_keywords("outliers=K replaces; gaps='nan': the whole record") == \
        "--outliers K replaces; --gaps nan: the whole record"
    assert option_keywords("the units and kind of n_samples") == "the units and kind of n_samples"
    payload = {"source": "units=deg/x.csv", "columns": {"dev": "units=x"},
               "data_quality": {"warnings": ["pass units= (deg/h)"]},
               "axes": [{"notes": ["give n_samples=N"], "plausibility": {"message": "(units=)"},
                         "outliers_effect": {"text": "outliers=8: replaced", "share": 0.1}}]}
    assert cli_payload(payload) == {
        "source": "units=deg/x.csv", "columns": {"dev": "units=x"},
        "data_quality": {"warnings": ["pass --units (deg/h)"]},
        "axes": [{"notes": ["give --n-samples N"], "plausibility": {"message": "(--units)"},
                  "outliers_effect": {"text": "--outliers 8: replaced", "share": 0.1}}]}


def test_a_bag_with_several_imu_topics_names_the_topic_option(tmp_path: Path) -> None:
    """The Python side is tests/io/test_rosbag.py (``choose one with topic=NAME``)."""
    pytest.importorskip("rosbags")
    from tests.io.test_rosbag import _write_ros2

    _write_ros2(tmp_path / "two", topics=("/imu0", "/imu1"))
    res = runner.invoke(app, ["info", str(tmp_path / "two")])
    assert res.exit_code == 2
    lines = error_output(res.stderr).splitlines()
    assert len(lines) == 1 and lines[0].endswith(
        "has several IMU topics (/imu0, /imu1); choose one with --topic NAME")


def test_split_of_burst_logged_stamps_names_the_argument() -> None:
    """The CLI side is tests/cli/test_allan.py (``--gaps split needs regular stretches``)."""
    from fogts.preprocess.hygiene import assess_run
    from tests.conftest import shared_path

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run = fogts.read_run(shared_path("imu", "mpu6050_gyro_temp_converted.csv.gz"))
        with pytest.raises(DataError) as info:
            assess_run(run, gaps="split")
    message = str(info.value)
    assert "gaps='split' needs regular stretches between gaps" in message
    assert message.endswith("use gaps='warn' (the record at its mean rate)")
    assert "CLI" not in message and "--" not in message
