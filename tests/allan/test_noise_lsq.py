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


@pytest.mark.parametrize(("bend", "kept"), [(0.0, False), (0.1, False), (0.2, True)])
def test_the_model_error_verdict_quotes_its_own_test(bend: float, kept: bool) -> None:
    """Whether a model error is needed is decided by its likelihood-ratio test, not by the
    Pearson chi2 beside it (audit: "chi2 = 22.41 on 11 dof; no model error needed" with that
    chi2 at p ~ 0.02): the sentence quotes the test's statistic and p-value, and the verdict
    follows from them (p below the level <=> a model error is kept)."""
    import numpy as np

    from fogts.allan.noise_lsq import chi2_sentence, model_error_p_value
    from tests.allan.noise_cases import avar, make_result

    tau = 2.0 ** np.arange(-4, 12)
    dev = np.sqrt(avar(tau, N=0.02, B=0.1, K=0.5)) * (1 + bend * np.sin(np.arange(tau.size)))
    model = quiet_fit(make_result(tau, dev, edf=200.0), significance=0.05)
    lr, p = model.model_error_lr, model.model_error_p
    assert np.isfinite(lr) and lr >= 0 and p == pytest.approx(model_error_p_value(lr))
    assert (model.model_error > 0) == (p < 0.05) == kept
    text = chi2_sentence(model.chi2, model.dof, model.model_error, lr, 0.05)
    assert f"likelihood-ratio test {lr:.3g}, p = {p:.2g} " \
           f"{'<' if model.model_error > 0 else '>='} 0.05" in text
    assert text in model.summary()


def test_model_error_p_value_is_the_boundary_mixture() -> None:
    """0.5 P(chi2_1 > lr): the 5 % critical value z_0.95^2 = 2.706 gives p = 0.05; 0 gives 1;
    a sentence without a test (a model read back, OLS) keeps its old wording."""
    from scipy.stats import chi2

    from fogts.allan.noise_lsq import chi2_sentence, model_error_p_value

    assert model_error_p_value(2.705543) == pytest.approx(0.05, rel=1e-5)
    assert model_error_p_value(7.3) == pytest.approx(0.5 * chi2.sf(7.3, 1), rel=1e-9)
    assert model_error_p_value(0.0) == 1.0
    assert chi2_sentence(15.2, 17, 0.0) == \
        "chi2 = 15.2 on 17 dof; no model error needed (relative, on sigma^2)"
    assert chi2_sentence(15.2, 17, 0.0, 0.0, None).endswith(
        "likelihood-ratio statistic 0, p = 1 (no test level: any rise in the likelihood "
        "keeps one)")
