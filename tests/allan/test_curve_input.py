"""``fogts.allan.curve_input``: a published Allan curve as an AllanResult, checked against
the SMAC-Group/avar FOG curves (through ``tests.allan.noise_cases.smac_result``, whose fits
``test_noise.test_published_fog_curves`` compares with the sensors' published values),
Stable32 output and closed-form curves; and every refusal."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from fogts.allan.confidence import chi2_interval
from fogts.allan.curve_input import check_curve_methods, read_curve_file, read_curves
from fogts.allan.edf import edf_for
from fogts.allan.result import AllanResult, AllanResultSet
from fogts.errors import DataError, DataQualityWarning
from tests.allan.noise_cases import avar, quiet_fit, smac_result
from tests.allan.references import stable32_table
from tests.conftest import shared_path

FS = 100.0
TAU = 2.0 ** np.arange(0, 17) / FS            # 0.01 .. 655 s, octaves
N_REC = 4_000_000                             # 11 h at 100 Hz


def _write(tmp_path: Path, text: str, name: str = "c.csv") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def _curve_csv(tmp_path: Path, dev: np.ndarray, header: str = "tau,adev_deg_h",
               tau: np.ndarray = TAU) -> Path:
    rows = "".join(f"{float(t)!r},{float(d)!r}\n" for t, d in zip(tau, dev, strict=True))
    return _write(tmp_path, f"{header}\n{rows}")


def _terms(model: object) -> tuple[np.ndarray, np.ndarray]:
    terms = model.terms  # type: ignore[attr-defined]
    return (np.array([t.value for t in terms]),
            np.array([t.stderr if math.isfinite(t.stderr) else 0.0 for t in terms]))


@pytest.mark.parametrize(("sensor", "units"), [("kvh1750", "deg/s"), ("ln200", "rad/s"),
                                               ("imar", "rad/s")])
@pytest.mark.parametrize("channel", ["Gyro. X", "Gyro. Z"])
def test_smac_fog_curves_fit_as_the_reference_helper(sensor: str, units: str,
                                                     channel: str) -> None:
    """The same inputs as ``smac_result`` (taus, adev, edf = 1/(2 errors^2), fs and n from
    the header, the 2-sigma bounds): the same terms to rounding (1e-12 relative; the
    numbers are parsed by a different path, so a last bit may differ)."""
    path = shared_path("allan_curves", "smac_avar", f"{sensor}_av.csv")
    res = read_curve_file(path, units=units, channel=channel)
    ref = smac_result(sensor, units, channel)
    assert isinstance(res, AllanResult) and res.axis == channel
    assert (res.kind, res.fs_hz, res.n_samples, res.confidence) == (
        "oadev", ref.fs_hz, ref.n_samples, ref.confidence)
    np.testing.assert_array_equal(res.m, ref.m)
    np.testing.assert_allclose(res.edf, ref.edf, rtol=1e-12)
    got, want = quiet_fit(res), quiet_fit(ref)
    for a, b in zip(_terms(got), _terms(want), strict=True):
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=0)


def test_closed_form_curve_round_trip(tmp_path: Path) -> None:
    """sigma^2 = N^2/tau + 2 ln2/pi B^2 + K^2 tau/3 exactly (IEEE 952 Annex C): the fit
    returns N, B, K to 1e-6 (an exact curve leaves only the solver's tolerance).  fogts
    reads B off the plateau with IEEE 952's rounded 0.664 (DESIGN.md), not
    sqrt(2 ln2 / pi) = 0.66428, hence B's truth here."""
    dev = np.sqrt(avar(TAU, N=0.02, B=0.01, K=0.5))
    res = read_curve_file(_curve_csv(tmp_path, dev), fs_hz=FS, n_samples=N_REC)
    assert isinstance(res, AllanResult) and res.units == "deg/h"
    assert set(res.alpha_method) == {"slope"}
    np.testing.assert_allclose(res.edf, edf_for("oadev", res.alpha, res.m, N_REC + 1))
    model = quiet_fit(res, terms="N,B,K", significance=None)
    b_truth = 0.01 * math.sqrt(2 * math.log(2) / math.pi) / 0.664
    for name, truth in (("N", 0.02), ("B", b_truth), ("K", 0.5)):
        assert model[name].value == pytest.approx(truth, rel=1e-6)


def test_stable32_edf_from_its_alpha_gives_its_bounds() -> None:
    """PHASE.DAT octave oadev: alphas as in the file, fs from AF/Tau, N from the data
    points; fogts' EDF for that alpha reproduces Stable32's MinSigma/MaxSigma to 1e-3
    (the file prints 5 digits; the existing confidence checks reach 5.6e-4)."""
    res = read_curve_file(shared_path("stable32", "phasedat", "phase_dat_oadev_octave.txt"),
                          units="deg/h")
    ref = stable32_table("phasedat", "phase_dat_oadev_octave.txt")
    assert isinstance(res, AllanResult)
    assert (res.kind, res.fs_hz, res.n_samples, res.confidence) == ("oadev", 1.0, 1000, 0.683)
    np.testing.assert_array_equal(res.tau_s, ref[:, 1])
    np.testing.assert_array_equal(res.dev, ref[:, 5])
    np.testing.assert_array_equal(res.alpha, ref[:, 3])
    np.testing.assert_array_equal(res.n, ref[:, 2])
    assert set(res.alpha_method) == {"file"}
    np.testing.assert_allclose(res.edf, edf_for("oadev", ref[:, 3], ref[:, 0], 1001))
    lo, hi = chi2_interval(res.dev, res.edf, 0.683)
    np.testing.assert_allclose(lo, ref[:, 4], rtol=1e-3)
    np.testing.assert_allclose(hi, ref[:, 6], rtol=1e-3)


def test_stable32_totdev_is_marked_bias_corrected() -> None:
    res = read_curve_file(shared_path("stable32", "ocxo", "totdev_octave.txt"), units="deg/h")
    assert isinstance(res, AllanResult) and res.kind == "totdev" and res.bias_corrected
    assert any("bias-corrected where it identified FM noise" in n for n in res.notes)


def test_inferred_sample_rate_and_record_length_are_said(tmp_path: Path) -> None:
    tau = TAU[3:]                                   # shortest tau 0.08 s
    text = "tau,adev,edf\n" + "".join(f"{float(t)!r},{1 / math.sqrt(t)!r},{float(1e5 / t)!r}\n"
                                       for t in tau)
    got = read_curves(_write(tmp_path, text), units="deg/h")
    p = got.provenance
    assert (p.fs_hz, p.fs_source, p.n_source) == (12.5, "inferred", "estimated")
    assert p.n_samples == round(1 * (1e5 / 0.08 + 1))
    assert any("the shortest tau, 0.08 s, taken as the sample interval (fs = 12.5 Hz); give "
               "fs_hz= if the record was sampled faster" in n for n in p.notes)
    assert any("the record length is not stated" in n for n in got.curves[0].notes)
    assert p.weights == "the edf column" and p.to_dict()["fs_source"] == "inferred"


def test_units_given_from_the_name_or_assumed_with_a_warning(tmp_path: Path) -> None:
    dev = np.sqrt(avar(TAU, N=0.02))
    named = read_curves(_curve_csv(tmp_path, dev, "tau,adev_rad_s"), n_samples=N_REC)
    assert (named.provenance.units, named.provenance.units_source) == ("rad/s", "column name")
    given = read_curves(_curve_csv(tmp_path, dev, "tau,adev_rad_s"), units="deg/s",
                        n_samples=N_REC)
    assert (given.provenance.units, given.provenance.units_source) == ("deg/s", "given")
    with pytest.warns(DataQualityWarning, match=r"c.csv: no unit in the deviation column "
                                                r"'adev'; assuming deg/h; pass units= "):
        bare = read_curves(_curve_csv(tmp_path, dev, "tau,adev"), n_samples=N_REC)
    assert bare.provenance.units_assumed


def test_a_variance_column_is_rooted_and_checked_against_the_deviation(tmp_path: Path) -> None:
    dev = np.sqrt(avar(TAU, N=0.02))
    rows = "".join(f"{float(t)!r},{float(d * d)!r}\n" for t, d in zip(TAU, dev, strict=True))
    res = read_curve_file(_write(tmp_path, "tau,avar\n" + rows), units="deg/h",
                          n_samples=N_REC)
    assert isinstance(res, AllanResult)
    np.testing.assert_allclose(res.dev, dev, rtol=1e-15)
    assert "deviation = sqrt of the variance column 'avar'" in res.notes
    bad = "tau,avar,adev\n0.01,4,2\n0.02,1,1.1\n"
    with pytest.raises(DataError, match=r"the deviation 'adev' = 1.1 and the root of the "
                                        r"variance 'avar' = 1 disagree at line 3"):
        read_curve_file(_write(tmp_path, bad), units="deg/h", n_samples=N_REC)
    with pytest.raises(DataError, match=r"column 'avar' has the negative variance -1 at "
                                        r"line 3; a variance must be >= 0"):
        read_curve_file(_write(tmp_path, "tau,avar\n0.01,4\n0.02,-1\n"), units="deg/h",
                        n_samples=N_REC)


def test_bounds_are_the_files_or_chi_squared_from_the_edf(tmp_path: Path) -> None:
    """Without bounds, the chi-squared interval of each point's EDF (NIST SP1065 5.3) at
    the level asked; the file's bounds are kept, their level said when not stated."""
    plain = _write(tmp_path, "tau,adev,edf\n0.01,1,100\n0.02,0.7,50\n")
    res = read_curve_file(plain, units="deg/h", confidence=0.9)
    assert isinstance(res, AllanResult) and res.confidence == 0.9
    lo, hi = chi2_interval(res.dev, res.edf, 0.9)
    np.testing.assert_allclose(res.ci_low, lo)
    np.testing.assert_allclose(res.ci_high, hi)
    assert any("chi-squared at 90.0 % from the EDF" in n for n in res.notes)
    bounded = _write(tmp_path, "tau,adev,lower,upper,edf\n0.01,1,0.9,1.1,100\n", "b.csv")
    res = read_curve_file(bounded, units="deg/h")
    assert isinstance(res, AllanResult) and res.ci_low.tolist() == [0.9]
    assert "bounds: the file's, level not stated (taken as 68.3 %)" in res.notes


def _channels_csv(tmp_path: Path) -> Path:
    lines = ["channel,tau,adev,edf"]
    for ch in ("Gyro. X", "Gyro. Y", "Accel. X"):
        lines += [f"{ch},{float(t)!r},{1 / math.sqrt(t)!r},{float(1e5 / t)!r}" for t in TAU]
    return _write(tmp_path, "\n".join(lines) + "\n")


def test_channels_default_all_of_the_unit_quantity_or_named(tmp_path: Path) -> None:
    path = _channels_csv(tmp_path)
    both = read_curves(path, units="rad/s", fs_hz=FS)
    assert isinstance(both.result, AllanResultSet)
    assert both.provenance.channels == ("Gyro. X", "Gyro. Y")
    assert any("left out the channels Accel. X" in n for n in both.provenance.notes)
    assert read_curves(path, units="m/s^2", fs_hz=FS).provenance.channels == ("Accel. X",)
    assert len(read_curves(path, units="rad/s", fs_hz=FS, channel="all").curves) == 3
    one = read_curve_file(path, units="rad/s", fs_hz=FS, channel="gyro. y")
    assert isinstance(one, AllanResult) and one.axis == "Gyro. Y"
    with pytest.raises(DataError, match=r"channel 'Gyro. W' not found in .*c.csv; channels "
                                        r"are: Gyro. X, Gyro. Y, Accel. X \(or 'all'\)"):
        read_curve_file(path, units="rad/s", fs_hz=FS, channel="Gyro. W")


# --------------------------------------------------------------------------- refusals


@pytest.mark.parametrize(("text", "kwargs", "match"), [
    ("tau,adev,edf\n0.01,1,9\n0,1,9\n", {}, r"column 'tau' has 0.0 at line 3; every tau must "
                                           r"be a finite number > 0 s"),
    ("tau,adev,edf\n0.02,1,9\n0.01,1,9\n", {}, r"column 'tau' does not increase at line 3 "
                                              r"\(0.02 s, then 0.01 s\)"),
    ("tau,adev,edf\n0.01,1,9\n0.02,-1,9\n", {}, r"column 'adev' has -1.0 at line 3; a "
                                               r"deviation must be a finite number >= 0"),
    ("tau,adev,edf\n0.01,1,9\n0.02,,9\n", {}, r"column 'adev' has nan at line 3"),
    ("tau,adev,edf\n0.01,1,9\nnan,1,9\n", {}, r"column 'tau' has nan at line 3"),
    ("tau,adev,edf\n0.01,1,9\n0.025,1,9\n", {"fs_hz": FS},
     r"tau = 0.025 s at line 3 is not a whole number of samples at fs = 100 Hz \(tau fs = "
     r"2.5\); taus must be m / fs"),
    ("tau,m,adev,edf\n0.01,1,1,9\n0.02,2,1,9\n", {"fs_hz": 200.0},
     r"column 'm' says m = 1 at line 2, but tau fs = 2 at fs = 200 Hz; give the record's "
     r"fs_hz= \(100 Hz by the file\)"),
    ("tau,adev,edf\n0.01,1,9\n0.02,1,0\n", {}, r"column 'edf' has 0.0 at line 3; edf must be "
                                              r"a finite number > 0"),
    ("tau,adev,errors\n0.01,1,0.1\n0.02,1,nan\n", {}, r"column 'errors' has nan at line 3"),
    ("tau,adev\n0.01,1\n0.02,0.7\n", {}, r"needs each point's weight, and this curve has "
                                         r"neither an edf nor an errors column, nor the record "
                                         r"length to compute them: give n_samples=N \(the number"),
    ("tau,adev\n0.01,1\n0.02,0.7\n", {"n_samples": 3},
     r"n_samples = 3 is too short for this curve .*; give the record's own n_samples=N$"),
    ("tau,adev,alpha\n0.01,1,5\n0.02,0.7,0\n", {"n_samples": 1000},
     r"c.csv: column 'alpha': alpha must be an integer in \[-2, 2\] for kind='adev', got 5"),
    ("tau,adev,edf\n0.01,1,9\n", {"channel": "x"}, r"channel 'x': .* has no channel column "
                                                   r"\(one curve\); leave out channel=$"),
    ("tau,adev,edf\n0.01,1,9\n", {"kind": "xdev"}, r"kind must be one of adev, oadev"),
    ("tau,adev,edf\n0.01,1,9\n", {"fs_hz": -1.0}, r"fs_hz must be a finite number > 0, got -1.0"),
    ("tau,adev,edf\n0.01,1,9\n", {"n_samples": 1}, r"n_samples must be .*>= 2"),
    ("tau,adev,edf\n0.01,1,9\n", {"confidence": 2.0}, r"confidence must be in \(0, 1\)"),
    ("tau,adev,edf\n0.01,1,9\n", {"units": "furlong"},
     r"units must be a rate unit \(deg/h, deg/s, rad/s, arcsec/s\) or a specific-force unit "
     r".*got 'furlong'"),
])
def test_every_refusal_names_the_value_and_what_is_allowed(tmp_path: Path, text: str,
                                                           kwargs: dict, match: str) -> None:
    kw = {"units": "deg/h", **kwargs}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DataQualityWarning)
        with pytest.raises(DataError, match=match):
            read_curve_file(_write(tmp_path, text), **kw)


def test_methods_a_curve_cannot_support_are_refused(tmp_path: Path) -> None:
    path = _write(tmp_path, "tau,adev,edf\n0.01,1,9\n0.02,0.7,5\n")
    estimated = read_curves(path, units="deg/h").provenance
    check_curve_methods(["wls", "gls", "ols"], estimated)
    with pytest.raises(DataError, match=r"method 'ml' fits the recording itself .*; run "
                                        r"'fogts allan RECORDING --method ml'"):
        check_curve_methods(["wls", "ml"], estimated)
    with pytest.raises(DataError, match=r"method 'gmwm' needs the record length .* give "
                                        r"n_samples=N, or fit with wls"):
        check_curve_methods(["gmwm"], estimated)
    check_curve_methods(["gmwm"], read_curves(path, units="deg/h", n_samples=1000).provenance)
    with pytest.raises(DataError, match=r"method must be one of wls, gls, ols, gmwm for a "
                                        r"curve; got 'lsq'"):
        check_curve_methods(["lsq"], estimated)


# --------------------------------------------------------------------------- wording


def _bare_channels_csv(tmp_path: Path) -> Path:
    """Nothing stated but the taus, the deviations and their EDF: no unit, estimator,
    sample rate or record length; a gyro and an accelerometer channel."""
    lines = ["channel,tau,dev,edf"]
    for ch in ("Gyro. X", "Accel. X"):
        lines += [f"{ch},{float(t)!r},{1 / math.sqrt(t)!r},{float(1e5 / t)!r}" for t in TAU]
    return _write(tmp_path, "\n".join(lines) + "\n", "bare.csv")


#: What each inference note suggests, as read_curve_file's keyword (the command line's
#: option is tests/cli/test_curve.py's ``test_inference_notes_name_the_options``).
CURVE_NOTE_KEYWORDS = {
    "the estimator is not stated": "give kind=",
    "left out the channels Accel. X": "pick one with channel=NAME and its units=",
    "the sample rate is not stated": "give fs_hz= if the record was sampled faster",
    "the record length is not stated": "give n_samples=N",
}


def test_inference_notes_and_the_unit_warning_name_the_keywords(tmp_path: Path) -> None:
    """In Python the notes and the warning name read_curve_file's keywords (``units=``,
    ``kind=``, ``fs_hz=``, ``n_samples=``, ``channel=``), never an option (``--units``)."""
    with pytest.warns(DataQualityWarning) as caught:
        got = read_curves(_bare_channels_csv(tmp_path))
    (warning,) = [str(w.message) for w in caught if "no unit" in str(w.message)]
    assert warning == ("bare.csv: no unit in the deviation column 'dev'; assuming deg/h; pass "
                       "units= (deg/h, deg/s, rad/s, arcsec/s)")
    notes = got.provenance.notes
    for start, keyword in CURVE_NOTE_KEYWORDS.items():
        (note,) = [n for n in notes if n.startswith(start)]
        assert note.endswith(keyword), note
    assert got.curves[0].notes[:len(notes)] == notes
    assert not any("--" in n for n in (*notes, warning))
