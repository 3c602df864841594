"""The HTML report (fogts.report.html and the modules it builds on): sections, escaping of
untrusted strings, self-containment, figures, and the numbers it shows are the library's;
plus ``fogts report`` on the command line.

(The rendering in a real browser is tests/report/test_browser.py.)
"""

from __future__ import annotations

import base64
import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from markupsafe import escape
from typer.testing import CliRunner

from fogts.errors import DataError, ModelFitError
from fogts.io.reader import read_run
from fogts.report.html import (
    DAVAR_MIN_WINDOW_SAMPLES,
    DAVAR_MIN_WINDOWS,
    HtmlReport,
    build_report,
    write_report,
)
from fogts.report.text import json_dumps
from tests.conftest import shared_path

runner = CliRunner()
EVIL = "<script>alert(1)</script>"
EVIL_NAME = "<img src=x onerror=alert(2)>"  # no '/': it is a file name


def _write_recording(path: Path, *, n: int = 6_000, temperature: bool = True,
                     seed: int = 5) -> None:
    """10 Hz (10 min by default): white noise + a rate random walk + a warm-up thermal drift."""
    rng = np.random.default_rng(seed)
    fs = 10.0
    t = np.arange(n) / fs
    temp = 20.0 + 12.0 * (1.0 - np.exp(-t / 700.0)) + rng.normal(0.0, 0.02, n)
    rate = 0.4 + rng.normal(0.0, 0.3, n) + np.cumsum(rng.normal(0.0, 0.002, n))
    cols = [t, rate]
    header = "time,rate"
    if temperature:
        rate += 0.03 * temp
        cols = [t, rate, temp]
        header += ",T"
    with path.open("w") as fh:
        fh.write(f"# operator {EVIL} & <b>bench</b>\n")
        fh.write(f"{header},{EVIL}\n")
        np.savetxt(fh, np.c_[(*cols, np.ones(n))], delimiter=",", fmt="%.6f")


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> tuple[HtmlReport, str, Path]:
    folder = tmp_path_factory.mktemp("report")
    src = folder / f"unit {EVIL_NAME}.csv"  # an untrusted file name, too
    _write_recording(src)
    rep = build_report(read_run(src), title=f"Unit 7 {EVIL}")
    out = write_report(folder / "report.html", rep)
    return rep, out.read_text(encoding="utf-8"), src


def test_every_section_present_and_ok(built: tuple[HtmlReport, str, Path]) -> None:
    rep, _, _ = built
    ids = [s.id for s in rep.sections]
    assert ids == ["summary", "input", "timeseries", "allan-1", "arma-1", "prediction-1", "davar-1",
                   "thermal-1"]
    bad = [(s.id, s.message) for s in rep.sections if s.status != "ok"]
    assert bad == []
    assert rep.omitted == ()
    # a figure in every section that draws one
    figs = {s.id: len(s.figures) for s in rep.sections}
    assert figs["timeseries"] == 1 and figs["allan-1"] == 1 and figs["prediction-1"] == 1
    assert figs["davar-1"] == 1 and figs["thermal-1"] >= 1
    assert "report" in rep.summary() and len(rep.to_frame()) == len(rep.sections)
    assert json_dumps(rep.to_dict())  # JSON-safe
    # methods are named by what they compute (README "Methods and references"), never by
    # internal labels such as "seed 000"
    _, html, _ = built
    assert "seed" not in html.lower() and "ρ_a,2 = Σ a_t a_{t−2} / Σ a_t²" in html


def test_each_section_says_how_to_read_it_in_one_sentence(
        built: tuple[HtmlReport, str, Path]) -> None:
    rep, text, _ = built
    for s in rep.sections:
        how = s.how_to_read
        assert how.endswith(".") and how[0].isupper(), s.id
        assert re.search(r"[.!?]\s+[A-Z]", how) is None, f"{s.id}: more than one sentence"
        assert str(escape(how)) in text
    assert text.count('<p class="how">') == len(rep.sections)


def test_untrusted_strings_are_escaped(built: tuple[HtmlReport, str, Path]) -> None:
    _, text, _ = built
    # the header cell, the comment line, the file name and the title are all shown as text
    assert text.count("&lt;script&gt;alert(1)&lt;/script&gt;") >= 3  # header, comment, title
    assert "&lt;b&gt;bench&lt;/b&gt;" in text
    assert "&lt;img src=x onerror=alert(2)&gt;" in text
    # ... and nothing in the document is a script, an injected tag or an event handler
    assert "<script" not in text.lower() and "<img src=x" not in text
    assert re.search(r"<[a-z][^>]*\son[a-z]+\s*=", text) is None


def test_document_is_self_contained(built: tuple[HtmlReport, str, Path]) -> None:
    _, text, _ = built
    refs = re.findall(r'\s(?:src|href)="([^"]*)"', text)
    assert refs, "no figure found"
    assert all(r.startswith(("data:image/svg+xml;base64,", "data:image/png;base64,", "#"))
               for r in refs), [r[:40] for r in refs if not r.startswith(("data:", "#"))]
    assert "<link" not in text and "@import" not in text and "url(" not in text
    assert "default-src 'none'" in text  # the CSP forbids loading anything else


def test_figures_are_valid_images(built: tuple[HtmlReport, str, Path]) -> None:
    rep, _, _ = built
    for s in rep.sections:
        for f in s.figures:
            raw = base64.b64decode(f.data)
            if f.mime == "image/svg+xml":
                root = ET.fromstring(raw)
                assert root.tag.endswith("svg")
                assert len(list(root.iter())) > 50, f.id  # drawn, not empty
            else:
                assert raw[:8] == b"\x89PNG\r\n\x1a\n"
            assert f.width > 100 and f.height > 100


@pytest.mark.filterwarnings("ignore::fogts.errors.UnidentifiableTermWarning")
def test_report_numbers_are_the_library_numbers(built: tuple[HtmlReport, str, Path]) -> None:
    from fogts.allan import allan_deviation
    from fogts.allan.noise import fit_noise
    from fogts.arma import select_arma
    from fogts.preprocess.prepare import prepare
    from fogts.startup.thermal_fit import fit_thermal

    rep, text, src = built
    run = read_run(src)
    model = fit_noise(allan_deviation(run, axis=0))
    table = next(b for b in next(s for s in rep.sections if s.id == "allan-1").blocks
                 if b.kind == "table")
    n_row = next(r for r in table.rows if r[0] == "N")
    assert float(n_row[2]) == pytest.approx(model["N"].value, rel=1e-3)  # 4 digits shown
    sel = select_arma(prepare(run, axis=0, stationarity=False))  # same series, no ADF
    assert f"Selected model: {sel.best.name}" in text
    gm = sel.gauss_markov()  # ARMA(1,1), T_c 682 s (95 %: over 192 s; measured)
    assert gm is not None and str(escape(gm.summary())) in text
    thermal = fit_thermal(run.axis(0), run.temperature, fs_hz=run.fs_hz, units=run.units)
    assert str(escape(thermal.equation())) in text
    # the drift simulated as 0.03 * T over 10 min (0.2 deg/h) is not told from the random
    # walk (p = 0.26, measured), so the report, as the library, subtracts nothing
    block = next(b for b in next(s for s in rep.sections if s.id == "thermal-1").blocks
                 if b.kind == "table" and b.caption.startswith("Bias stability"))
    before, after = float(block.rows[0][1]), float(block.rows[1][1])
    assert after == before and str(block.rows[1][0]).startswith("after (nothing compensated")


def test_short_record_without_temperature_omits_davar_and_thermal(tmp_path: Path) -> None:
    n = DAVAR_MIN_WINDOWS * DAVAR_MIN_WINDOW_SAMPLES - 1
    src = tmp_path / "short.csv"
    _write_recording(src, n=n, temperature=False)
    rep = build_report(read_run(src), parts=("timeseries", "davar", "thermal"))
    assert [s.id for s in rep.sections] == ["timeseries"]
    reasons = dict(rep.omitted)
    assert f"{n:,} samples" in reasons["Dynamic Allan deviation"]
    assert "no temperature column" in reasons["Thermal model"]
    # read_run's keyword (fogts report says --temperature-column: tests/cli/test_report.py)
    assert reasons["Thermal model"].endswith("or pass temperature_column=)")
    text = rep.render()
    assert 'id="not-included"' in text and "no temperature column" in text


def test_a_given_davar_window_that_does_not_fit_says_so(tmp_path: Path) -> None:
    # audit2: --davar-window 1e9 on a 10,000 s record said "the record has 1,000,000
    # samples; ... needs at least 10 windows of 256 samples (2,560 samples)"
    src = tmp_path / "r.csv"
    _write_recording(src, n=6_000, temperature=False)  # 600 s at 10 Hz
    run = read_run(src)
    for window in (1e9, 1.0):
        rep = build_report(run, parts=("davar",), davar_window_s=window)
        reason = dict(rep.omitted)["Dynamic Allan deviation"]
        assert reason.startswith(f"the given window ({window:g} s) does not fit this record")
        assert "may be 25.6 .. 60 s" in reason and "6,000 samples" not in reason
    rep = build_report(run, parts=("davar",), davar_window_s=30.0)
    assert not rep.omitted


def test_a_failing_part_becomes_an_error_section(tmp_path: Path,
                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    import fogts.report.analyses as analyses

    def broken(self: object, i: int) -> object:
        raise ModelFitError(f"every candidate failed {EVIL}")

    monkeypatch.setattr(analyses.ReportContext, "get_selection", broken)
    src = tmp_path / "r.csv"
    _write_recording(src, n=3000, temperature=False)
    rep = build_report(read_run(src), parts=("timeseries", "arma", "prediction"))
    status = {s.id: (s.status, s.message) for s in rep.sections}
    assert status["timeseries"][0] == "ok"
    assert status["arma-1"] == ("error", f"every candidate failed {EVIL}")
    assert status["prediction-1"][0] == "error"
    text = rep.render()
    assert "This part could not be computed: every candidate failed &lt;script&gt;" in text


def test_multi_axis_run_gives_one_section_per_axis(tmp_path: Path) -> None:
    rng = np.random.default_rng(2)
    run = read_run(rng.normal(size=(4000, 2)), fs_hz=10.0)
    rep = build_report(run, parts=("allan",))
    assert [s.id for s in rep.sections] == ["allan-1", "allan-2"]
    assert all(s.status == "ok" for s in rep.sections)
    assert rep.sections[1].title.endswith(f"axis {run.axes[1]}")


def test_summary_opens_the_report_with_every_axis_and_the_spec(tmp_path: Path) -> None:
    """The summary section: one row per axis with the Allan sections' own N (in the chosen
    units), and the spec verdict naming the failing terms (N far above its limit) and those
    the data cannot decide (B, not measured on white noise); each axis' warnings stay notes of
    its Allan section, although the summary computed the analysis first."""
    from fogts.allan.datasheet import NoiseSpec
    from fogts.units import TERM_SI_FACTOR

    rng = np.random.default_rng(2)
    run = read_run(rng.normal(size=(4000, 2)), fs_hz=10.0)
    spec = NoiseSpec.from_mapping({"units": "si", "N": 1e-9, "B": 1e-12}, source="ds.yaml")
    rep = build_report(run, parts=("allan", "summary"), output_units="si", spec=spec)
    assert [s.id for s in rep.sections] == ["summary", "allan-1", "allan-2"]
    summary = rep.sections[0]
    table = next(b for b in summary.blocks if b.kind == "table")
    assert table.columns[:3] == ("file", "axis", "N (rad/s/sqrt(Hz))")
    assert [r[1] for r in table.rows] == list(run.axes)
    n_si = float(table.rows[0][2].split(" ± ")[0])
    # white noise of unit variance at 10 Hz in deg/h: N = sqrt(1/10)/60 deg/sqrt(h)
    assert n_si == pytest.approx(math.sqrt(0.1) / 60 * TERM_SI_FACTOR["N"], rel=0.05)
    verdict = next(b for b in summary.blocks if b.kind == "verdict")
    assert not verdict.good and verdict.text.startswith(
        f"Spec ds.yaml: FAIL for {run.axes[0]}: N, {run.axes[1]}: N; INCONCLUSIVE for "
        f"{run.axes[0]}: B, {run.axes[1]}: B (the limit lies within the estimate's ")
    assert all(s.notes for s in rep.sections[1:]) and not summary.notes


def test_bad_arguments(tmp_path: Path) -> None:
    run = read_run(np.random.default_rng(0).normal(size=500), fs_hz=10.0)
    with pytest.raises(DataError, match="parts must be one of .*; got 'overview'"):
        build_report(run, parts=("input", "overview"))
    with pytest.raises(DataError, match="output_units must be one of deg, si; got 'mrad'"):
        build_report(run, output_units="mrad")  # type: ignore[arg-type]
    with pytest.raises(DataError, match="kind must be one of .*; got 'xdev'"):
        build_report(run, kind="xdev")
    with pytest.raises(DataError, match="taus must be one of .*; got 'weekly'"):
        build_report(run, taus="weekly")
    with pytest.raises(DataError, match="criterion must be one of .*; got 'r2'"):
        build_report(run, criterion="r2")
    with pytest.raises(DataError, match="bias_average_s must be a finite number > 0, got -1"):
        build_report(run, bias_average_s=-1)
    with pytest.raises(DataError, match="davar_window_s must be a finite number > 0, got 0"):
        build_report(run, davar_window_s=0)
    with pytest.raises(DataError, match=r"run must be a fogts Run .*got ndarray"):
        build_report(np.zeros(10))  # type: ignore[arg-type]


def test_cli_report(tmp_path: Path) -> None:
    from fogts.cli import app

    src = tmp_path / "r.csv"
    _write_recording(src, n=2000)
    out = tmp_path / "r.html"
    res = runner.invoke(app, ["report", str(src), "-o", str(out), "--title", "bench 3"])
    assert res.exit_code == 0, res.output
    assert f"wrote {out}" in res.output
    assert "not included: Dynamic Allan deviation" in res.output
    text = out.read_text()
    assert "<title>bench 3</title>" in text and text.rstrip().endswith("</html>")


def test_cli_report_bad_input_is_one_line_error(tmp_path: Path) -> None:
    from fogts.cli import app

    bad = tmp_path / "bad.csv"
    bad.write_text("time,rate\n0,1\n0.1,x\n0.2,2\n")
    res = runner.invoke(app, ["report", str(bad), "-o", str(tmp_path / "r.html")])
    assert res.exit_code == 2
    assert "error: column 'rate' has non-numeric value 'x'" in res.output
    assert "Traceback" not in res.output and not (tmp_path / "r.html").exists()


def test_cli_report_output_must_be_html(tmp_path: Path) -> None:
    from fogts.cli import app

    src = tmp_path / "run.csv"
    src.write_text("time,rate\n" + "".join(f"{i / 10},{i % 3}\n" for i in range(50)))
    res = runner.invoke(app, ["report", str(src), "-o", str(tmp_path / "r.txt")])
    assert res.exit_code == 2
    assert res.stderr.strip() == ("error: --output must end in .html or .htm (the report is "
                                  "one HTML page); got 'r.txt'")
    assert not (tmp_path / "r.txt").exists()


def test_cli_report_on_a_real_fog_recording(tmp_path: Path) -> None:
    """61 s of a real FOG at 100 Hz with temperature: every section, the DAVAR one with the
    noise step it finds (the summary repeats it)."""
    from fogts.cli import app

    out = tmp_path / "fog.html"
    res = runner.invoke(app, ["report", str(shared_path("fog", "fog_0917.txt")), "-o",
                              str(out)])
    assert res.exit_code in (0, 1), res.output
    text = out.read_text()
    for title in ("Input and preprocessing", "Time series",
                  "Allan deviation and noise coefficients", "Thermal model"):
        assert title in text
    assert "time, fog, T" in text
    assert "Dynamic Allan deviation" in text
    assert text.count("noise level: NOT stationary") >= 1


def test_thermal_section_shows_the_out_of_sample_gain() -> None:
    """A significant model (the bundled cold start) gets the fold table and the sentence."""
    rep = build_report(read_run(Path(__file__).resolve().parents[2] / "data"
                                / "startup_cold_1hz.csv"), parts=("thermal",))
    blocks = next(s for s in rep.sections if s.id == "thermal-1").blocks
    table = next(b for b in blocks if b.kind == "table"
                 and b.caption.startswith("Bias stability out of sample (time blocks"))
    assert len(table.rows) == 5 and "not scored" in table.rows[0][0]
    assert any(b.kind == "paragraph" and b.text.startswith("Out of sample (5 time blocks")
               for b in blocks)
    # one warm-up: the coefficients are not separately identified, said as a failed verdict
    note = [b for b in blocks if b.kind == "verdict" and not b.good]
    assert len(note) == 1
    assert note[0].text.startswith("The coefficients are not separately identified")


def test_thermal_section_gives_the_summary_reason_for_no_claim(tmp_path: Path) -> None:
    """A temperature span under 1 °C: the thermal model is not testable, so it is not
    applied, and the HTML rows give that reason, as the terminal does (not "model not
    significant", a different verdict from the block above them)."""
    rng = np.random.default_rng(4)
    n = 4000
    t = np.arange(n) / 10.0
    src = tmp_path / "flat.csv"
    pd.DataFrame({"time": t, "rate_deg_h": rng.normal(0.0, 0.3, n),
                  "T": 25.0 + 0.2 * np.sin(t / 50.0)}).to_csv(src, index=False)
    rep = build_report(read_run(src), parts=("thermal",))
    text = write_report(tmp_path / "r.html", rep).read_text(encoding="utf-8")
    assert "after (nothing compensated: the temperature spans 0.4 °C, too little to " \
           "identify its coefficients)" in text
    assert "Fitted drift model, not applied: the temperature spans 0.4 °C" in text
    assert "model not significant" not in text
    # the model's note of no significance (kept for a saved model) repeats the verdict:
    # the verdict is the only one said
    thermal = next(s for s in rep.sections if s.id == "thermal-1")
    assert thermal.blocks[0].kind == "verdict" and "less than 1 °C" in thermal.blocks[0].text
    assert [b.kind for b in thermal.blocks].count("verdict") == 1
    assert "do not reuse it to compensate another run" not in text


def test_source_line_of_a_record_on_its_regular_grid() -> None:
    # gaps='nan': the count is the grid's, and the line says how many points are missing
    import pandas as pd

    from fogts.preprocess.hygiene import assess_run

    t = np.r_[np.arange(3000), np.arange(3050, 6000)] / 10.0
    rate = np.random.default_rng(4).standard_normal(t.size)
    run, quality = assess_run(read_run(pd.DataFrame({"time": t, "rate": rate}), units="deg/h"),
                              gaps="nan")
    rep = build_report(run, quality=quality, parts=("timeseries",))
    assert "6,000 samples at 10 Hz (" in rep.source
    assert rep.source.endswith("; 50 of them missing (NaN) in the time stamps' gaps), rate in "
                               "deg/h")
