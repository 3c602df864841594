"""The report's sections say what the terminal says: the noise level's verdict in the summary,
the noise fit's chi-square line and the curve read-outs in the Allan section, what the
stationarity tests test, and which axis a preprocessing note is about."""

from __future__ import annotations

import html
import re
import warnings
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from fogts.errors import FogtsWarning
from fogts.io.reader import read_run
from fogts.report.html import build_report
from fogts.report.page import Section
from fogts.report.text import fit_sentences
from tests.conftest import shared_path

runner = CliRunner()


def _halving(seed: int = 3) -> np.ndarray:
    """10 min of white rate noise at 10 Hz whose std halves at t = 300 s."""
    rng = np.random.default_rng(seed)
    return np.r_[rng.normal(0.0, 1.0, 3000), rng.normal(0.0, 0.5, 3000)]


def _texts(section: Section) -> list[str]:
    return [b.text for b in section.blocks if b.kind in ("paragraph", "verdict")]


def _section(rep: object, sid: str) -> Section:
    return next(s for s in rep.sections if s.id == sid)  # type: ignore[attr-defined]


def test_summary_carries_the_davar_verdict_when_the_noise_level_changes() -> None:
    """The summary's first verdict agrees with the DAVAR section at the end, in its words
    (the change time and ratio), and says the terms average over the change."""
    rep = build_report(read_run(_halving(), fs_hz=10.0), parts=("summary", "allan", "davar"))
    assert [s.id for s in rep.sections] == ["summary", "allan-1", "davar-1"]
    line = next(b for b in _section(rep, "summary").blocks
                if b.kind == "verdict" and "noise level" in b.text)
    assert not line.good
    assert re.match(r"noise level: NOT stationary in [0-9.]+ s windows \(DAVAR: most likely change "
                    r"at t = ", line.text)
    assert line.text.endswith("): the noise terms average over it")
    davar = next(b for b in _section(rep, "davar-1").blocks if b.kind == "verdict")
    change = re.search(r"most likely change at t = [^;]+", davar.text)
    assert change is not None and change.group(0) in line.text
    # the change is found near 300 s (a quarter-window step of 15 s), the deviation halved
    # (the ratio of two 3000-sample estimates: within 10 %)
    t = float(re.search(r"t = ([0-9.]+) s", line.text).group(1))  # type: ignore[union-attr]
    ratio = float(re.search(r"deviation x ([0-9.]+)", line.text).group(1))  # type: ignore[union-attr]
    assert abs(t - 300.0) < 60.0 and ratio == pytest.approx(0.5, rel=0.1)


def test_summary_says_a_steady_noise_level_is_stationary_and_nothing_without_davar() -> None:
    rng = np.random.default_rng(4)
    run = read_run(rng.normal(size=6000), fs_hz=10.0)
    rep = build_report(run, parts=("summary", "davar"))
    lines = [b for b in _section(rep, "summary").blocks if "noise level" in (b.text or "")]
    assert len(lines) == 1 and lines[0].good
    assert re.match(r"noise level: stationary in [0-9.]+ s windows \(DAVAR: non-stationarity "
                    r"score ", lines[0].text)
    alone = build_report(run, parts=("summary",))
    assert not any("noise level" in t for t in _texts(alone.sections[0]))


def test_summary_names_the_axis_of_each_noise_level_line() -> None:
    rng = np.random.default_rng(5)
    run = read_run(np.c_[_halving(), rng.normal(size=6000)], fs_hz=10.0)
    rep = build_report(run, parts=("summary", "davar"))
    lines = [b.text for b in rep.sections[0].blocks if "noise level" in (b.text or "")]
    assert [t.split(": noise level: ")[0] for t in lines] == list(run.axes)
    assert "NOT stationary" in lines[0] and "NOT stationary" not in lines[1]


def test_the_summary_is_built_last_but_shown_first(monkeypatch: pytest.MonkeyPatch) -> None:
    """Built last, the summary sees the DAVAR result the DAVAR section computed (once)."""
    import fogts.report.analyses as analyses

    calls: list[int] = []
    real = analyses.ReportContext.get_dynamic_allan

    def counted(self: analyses.ReportContext, i: int) -> object:
        calls.append(i)
        return real(self, i)

    monkeypatch.setattr(analyses.ReportContext, "get_dynamic_allan", counted)
    rep = build_report(read_run(_halving(), fs_hz=10.0), parts=("davar", "summary"))
    assert [s.id for s in rep.sections] == ["summary", "davar-1"] and calls == [0]


@pytest.mark.filterwarnings("ignore::fogts.errors.UnidentifiableTermWarning")
def test_allan_section_has_the_fit_line_and_the_curve_readouts() -> None:
    """The terminal's ``fit: chi2 ...`` line and read-out table (``fogts allan``), from the
    same objects."""
    from fogts.pipeline import AllanSettings, analyse_allan_axis

    run = read_run(_halving(), fs_hz=10.0)
    rep = build_report(run, parts=("allan",))
    section = rep.sections[0]
    axis = analyse_allan_axis(run, 0, AllanSettings())
    assert axis.model is not None
    fit = fit_sentences(axis.model)
    assert fit[0].startswith("fit: chi2 = ") and fit[0] in _texts(section)
    expected = axis.readout.table(run.units, run.axes[0])
    tables = [b for b in section.blocks if b.kind == "table" and b.caption == expected.title]
    assert len(tables) == 1
    assert tables[0].rows == tuple(tuple(r) for r in expected.cells())
    assert tables[0].rows[0][0] == "minimum"
    assert expected.caption in _texts(section)


@pytest.mark.filterwarnings("ignore::fogts.errors.UnidentifiableTermWarning")
def test_cli_allan_prints_the_same_fit_line(tmp_path: Path) -> None:
    from fogts.cli import app
    from fogts.pipeline import AllanSettings, analyse_allan_axis

    path = tmp_path / "r.npy"
    np.save(path, _halving())
    res = runner.invoke(app, ["allan", str(path), "--fs", "10", "--units", "deg/h"])
    assert res.exit_code == 0, res.output
    model = analyse_allan_axis(read_run(_halving(), fs_hz=10.0, units="deg/h"), 0,
                               AllanSettings()).model
    assert model is not None and fit_sentences(model)[0] in res.stdout


def test_preprocessing_says_the_stationarity_tests_test_the_level() -> None:
    rep = build_report(read_run(_halving(), fs_hz=10.0), parts=("input",))
    steps = next(b for b in rep.sections[0].blocks if b.kind == "list"
                 and b.caption.startswith("Preprocessing"))
    line = next(s for s in steps.items if "ADF" in s)
    assert re.fullmatch(r"level: stationary \(ADF p[=<][^,]+, KPSS p[=<>][^;]+; tests the mean, not "
                        r"the noise level\)", line), line
    assert not any(s.startswith("stationarity:") for s in steps.items)


class _NoteWarning(FogtsWarning):
    pass


@pytest.mark.parametrize("axes", [1, 2])
def test_preprocessing_notes_name_their_axis(axes: int, monkeypatch: pytest.MonkeyPatch
                                             ) -> None:
    """A warning of one axis' ARMA preparation is a note of the input section, prefixed with
    the axis' name when the run has several axes."""
    import fogts.report.analyses as analyses

    real = analyses.ReportContext.get_prepared

    def noisy(self: analyses.ReportContext, i: int) -> object:
        if i == axes - 1:
            warnings.warn("a note of the last axis", _NoteWarning, stacklevel=1)
        return real(self, i)

    monkeypatch.setattr(analyses.ReportContext, "get_prepared", noisy)
    rng = np.random.default_rng(6)
    run = read_run(rng.normal(size=(3000, axes)).squeeze(), fs_hz=10.0)
    rep = build_report(run, parts=("input",))
    prefix = f"{run.axes[-1]}: " if axes > 1 else ""
    assert [n for n in rep.sections[0].notes if "a note of" in n] == [
        prefix + "a note of the last axis"]


def test_real_fog_record_whose_noise_halves(tmp_path: Path) -> None:
    """The audit's record: fit ok and a stationary level, but the noise level changes near
    t = 30 s; the summary says so first."""
    from fogts.cli import app

    out = tmp_path / "r.html"
    res = runner.invoke(app, ["report", str(shared_path("fog", "fog_0917.txt")), "--units",
                              "deg/h", "-o", str(out)])
    assert res.exit_code in (0, 1), res.output
    text = out.read_text()
    summary = text[:text.index('id="input"')]
    assert re.search(r"noise level: NOT stationary in [0-9.]+ s windows \(DAVAR: most likely "
                     r"change at t = 29\.8", summary)
    assert "level: stationary (ADF p<0.0001, KPSS p>0.1; tests the mean, not the noise level)" \
        in html.unescape(text) and "stationarity: stationary" not in text
    assert "fit: chi2 = " in text and "falling (region B)" in text



def test_noise_level_line_of_a_small_significant_change() -> None:
    """Significant but below ``min_change``: stationary within it, with the change's size,
    in the words of the DAVAR section's sentence."""
    from fogts.allan.dynamic_result import Nonstationarity

    ns = Nonstationarity(tau_s=0.01, score=2.7, observed_var=2.7, expected_var=1.0, edf=50.0,
                         n_independent=10, pvalue=0.0039, level=0.05, stationary=True,
                         change_time_s=None, change_ratio=None, flagged_windows=(),
                         tau_scores=np.array([2.7]), significant=True, effect=0.0073,
                         min_change=0.1)
    assert ns.noise_level() == (
        "noise level: stationary within 10 % (DAVAR: non-stationarity score 2.7 at tau = "
        "0.01 s, p = 0.0039; the change is significant but only 0.73 %)")
    assert ns.summary().endswith(
        "windows): stationary within 10 % (the change is significant but only 0.73 %)")


def test_input_section_names_the_keywords() -> None:
    """Built in Python, the report's data-quality list names the keywords (``units=``,
    ``gaps='split'``, ``outliers=K``), as DataQuality.warnings() does, and the "rate unit
    from" row points to that list: the table is never rewritten for the command line
    (tests/cli/test_report.py), since its cells come from the input."""
    from fogts.preprocess.hygiene import assess_run
    from fogts.report.sections import QUALITY_CAPTION
    from tests.preprocess.test_hygiene import unnamed_gappy_frame

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run, quality = assess_run(read_run(unnamed_gappy_frame()))
        rep = build_report(run, quality=quality, parts=("input",))
    blocks = rep.sections[0].blocks
    rows = dict(next(b for b in blocks if b.caption == "What was read").rows)
    assert rows["rate unit from"] == "ASSUMED (no unit in the column names; see Data quality)"
    (found,) = [b.items for b in blocks if b.caption == QUALITY_CAPTION]
    assert found == tuple(quality.warnings())
    assert "assuming deg/h; pass units= (deg/h, deg/s, rad/s, arcsec/s)" in found[0]
    assert "(gaps='split' analyses the longest regular segment" in found[1]
    assert "(outliers=K replaces samples beyond K robust sigmas)" in found[2]
    assert not any("--" in f for f in found)


def test_the_parameter_table_never_rounds_a_coefficient_near_a_unit_root_to_1() -> None:
    """audit2: the report's parameter table printed ar.L1 = 0.99995 as "1" (a unit root to
    the reader) while the equation above it said 0.99995."""
    from fogts.report.blocks import fmt_num
    from fogts.report.sections import _estimate_cell

    assert fmt_num(0.99995) == "1"  # the table's plain 4-digit cell
    assert _estimate_cell("ar.L1", 0.99995) == "0.99995"
    assert _estimate_cell("ma.L1", -0.99981) == "-0.9998"
    assert _estimate_cell("ma.L1", -0.99997) == "-0.99997"
    assert _estimate_cell("ar.L2", np.float64(-0.01716)) == "-0.01716"
    assert _estimate_cell("sigma2", 902.4) == 902.4 and _estimate_cell("mean", 0.004) == 0.004
