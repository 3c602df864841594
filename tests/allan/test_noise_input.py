"""Tests for fogts.allan.noise_input: the curve a noise fit reads (checks, EDF, exclusions)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from fogts.allan import AllanResultSet
from fogts.allan.noise import fit_noise
from fogts.errors import DataError, DataQualityWarning, FogtsWarning, InsufficientDataError
from tests.allan.noise_cases import avar, make_result, nk_result, quiet_fit


def test_unusable_points_are_left_out_with_a_warning() -> None:
    tau = 2.0 ** np.arange(-4, 12)
    dev = np.sqrt(avar(tau, N=0.02, K=0.5))
    dev[3] = np.nan
    dev[5] = 0.0
    with pytest.warns(DataQualityWarning, match="2 tau"):
        model = quiet_fit(make_result(tau, dev), terms="N,K")
    assert model.excluded_tau_s == (tau[3], tau[5])
    assert model.tau_s.size == tau.size - 2


def test_edf_fallback_and_gls_fallback() -> None:
    tau = 2.0 ** np.arange(-4, 12)
    res = make_result(tau, np.sqrt(avar(tau, N=0.02, K=0.5)), edf=np.nan, n_samples=10**7)
    model = quiet_fit(res, terms="N,K")
    assert model.edf_source == "ieee952"
    np.testing.assert_allclose(model.edf, 10**7 / res.m - 1)
    # no m / n_samples / fs_hz: no model covariance, so no GLS and diagonal errors
    bare = SimpleNamespace(kind="adev", units="deg/h", axis="x", tau_s=tau, dev=res.dev,
                           edf=np.full(tau.size, 100.0))
    with pytest.warns(FogtsWarning, match="fitted with method='wls' instead"):
        model = quiet_fit(bare, terms="N,K", method="gls")
    assert model.method == "wls" and model.stderr_method.startswith("EDF diagonal")
    ols = quiet_fit(res, terms="N,K", method="ols")
    assert ols.stderr_method == "OLS residual variance" and math.isnan(ols.model_error)


# --------------------------------------------------------------------------- every raise


class _NoDev:
    tau_s = np.ones(3)
    units = "deg/h"
    kind = "oadev"


def test_input_errors() -> None:
    good = nk_result()
    with pytest.raises(DataError, match="multi-axis result set"):
        fit_noise(AllanResultSet(curves=(good,)))
    with pytest.raises(DataError, match="_NoDev lacks dev"):
        fit_noise(_NoDev())
    bad_kind = make_result(good.tau_s, good.dev, kind="mdev")
    with pytest.raises(DataError, match=r"kind must be one of adev, oadev, totdev .* got 'mdev'"):
        fit_noise(bad_kind)
    with pytest.raises(DataError, match="allan_result.units must be a rate unit"):
        fit_noise(_Fake(units="furlong/s"))
    with pytest.raises(DataError, match="1-D of equal length"):
        fit_noise(_Fake(dev=np.ones(3)))
    with pytest.raises(DataError, match="tau_s must be finite and > 0"):
        fit_noise(_Fake(tau_s=-nk_result().tau_s))
    with pytest.raises(DataError, match="strictly increasing"):
        fit_noise(_Fake(tau_s=nk_result().tau_s[::-1]))
    with pytest.raises(DataError, match=r"allan_result.edf must have the shape of tau_s"):
        fit_noise(_Fake(edf=np.ones(2)))
    with pytest.raises(DataError, match="no usable edf at tau = 0.0625 s"):
        fit_noise(_Fake(edf=np.full(good.tau_s.size, np.nan), n_samples=None))
    short = make_result(good.tau_s[:3], good.dev[:3])
    with pytest.raises(InsufficientDataError, match=r"3 usable taus \(0\.0625, 0\.125, 0\.25 s\), fewer than the 5 terms"):
        fit_noise(short)
    model = quiet_fit(good, terms="N,K")
    with pytest.raises(DataError, match="tau_s must be finite and > 0"):
        model.curve([0.0, 1.0])


class _Fake:
    """A duck-typed AllanResult with one field overridden."""

    def __init__(self, **override: object) -> None:
        base = nk_result()
        self.kind, self.units, self.axis = "oadev", "deg/h", "x"
        self.tau_s, self.dev, self.edf = base.tau_s, base.dev, base.edf
        self.m, self.n_samples, self.fs_hz = base.m, base.n_samples, base.fs_hz
        for k, v in override.items():
            setattr(self, k, v)


def test_the_fit_curve_keeps_the_results_intervals() -> None:
    """The usable points' bounds go with the curve (the B read-off judges the floor with
    them); a result without bounds, or with a malformed one, gives None (the read-off then
    uses 68.3 % intervals from the EDF)."""
    from fogts.allan.noise_input import read_fit_curve

    tau = 2.0 ** np.arange(0, 6)
    dev = np.array([1.0, 0.7, np.nan, 0.4, 0.35, 0.3])
    res = make_result(tau, dev, ci=(dev * 0.9, dev * 1.1))
    curve = read_fit_curve(res)
    assert curve.ci_low is not None and curve.ci_high is not None
    np.testing.assert_allclose(curve.ci_low, dev[np.isfinite(dev)] * 0.9, rtol=1e-15)
    assert read_fit_curve(make_result(tau, dev)).ci_low is None
    odd = SimpleNamespace(kind="oadev", units="deg/h", tau_s=tau, dev=dev,
                          edf=np.full(6, 100.0), ci_low=np.ones(3), ci_high=None)
    assert read_fit_curve(odd).ci_low is None and read_fit_curve(odd).ci_high is None
