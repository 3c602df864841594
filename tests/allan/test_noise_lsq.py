"""Tests for fogts.allan.noise_lsq: the covariance behind the fit's standard errors."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from fogts.allan import AllanResult, allan_deviation
from tests.allan.noise_cases import K_TRUE, N_TRUE, quiet_fit, white_plus_rw


@pytest.mark.parametrize(("kind", "method", "expected"), [
    ("adev", "wls", "sandwich with the model covariance of the adev estimates"),
    ("adev", "gls", "GLS with the model covariance of the adev estimates"),
    ("totdev", "wls", "sandwich with totdev EDF variances with the correlations of the "
                      "model covariance of the oadev estimates"),
    ("totdev", "gls", "GLS with totdev EDF variances with the correlations of the model "
                      "covariance of the oadev estimates"),
])
def test_adev_and_totdev_fits_use_a_covariance(kind: str, method: str, expected: str) -> None:
    """Octave adev and totdev curves of white + RW noise: the standard errors come from a
    covariance with the correlation between taus, and are wider than the EDF diagonal's."""
    y = white_plus_rw(3, n_deg_rt_h=N_TRUE, k_deg_h15=K_TRUE, fs_hz=10.0, n=100_000)
    res = allan_deviation(y, fs_hz=10.0, kind=kind)
    assert isinstance(res, AllanResult)
    model = quiet_fit(res, terms="N,K", method=method)
    assert model.method == method and model.stderr_method == expected
    assert model.to_dict()["fit"]["stderr_method"] == expected
    bare = SimpleNamespace(kind=kind, units=res.units, axis="x", tau_s=res.tau_s, dev=res.dev,
                           edf=res.edf)  # no m / n_samples: EDF diagonal
    diag = quiet_fit(bare, terms="N,K")
    assert diag.stderr_method.startswith("EDF diagonal")
    if method == "wls":
        assert model["K"].stderr > diag["K"].stderr


def test_every_tau_grid_fits_without_a_dense_covariance() -> None:
    """A grid of every tau (49,999 points on 1e5 samples) takes the EDF diagonal: its
    covariance is kept as a vector (a dense 49,999^2 matrix would need 20 GB).  White rate
    noise N = 0.01 deg/sqrt(h) at 10 Hz, seed 3: recovered within 2 % (its standard error
    on this record is ~0.3 %)."""
    import warnings

    import numpy as np

    import fogts

    x = 0.01 * 60.0 * np.sqrt(10.0) * np.random.default_rng(3).standard_normal(100_000)
    res = fogts.allan_deviation(x, fs_hz=10.0, taus="all")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = fogts.fit_noise(res)
    assert model.stderr_method.startswith("EDF diagonal")
    assert abs(model["N"].value / 0.01 - 1.0) < 0.02
