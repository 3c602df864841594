"""Newton's method on the exact likelihood: extra starts on a redundant model and the
long-record path (presample, analytic Hessian)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import fogts.arma.fit as fitmod
import fogts.arma.optimiser as optimiser
from fogts.arma.fit import fit_arma
from fogts.arma.likelihood import ExactLikelihood
from fogts.arma.start_values import hannan_rissanen
from tests.arma.references import (
    AIC_TOL,
    PARAM_TOL,
    near_redundant,
    simulate,
    sm_fit,
)


def test_nearly_redundant_fit_tries_more_starts() -> None:
    """ARMA(1,1) on white noise: the likelihood has several maxima along the cancellation
    ridge phi = -theta; from the Hannan-Rissanen start alone Newton ends 0.8 llf lower, the
    extra starts (mirrored pair, statsmodels' start values) find the better maximum."""
    n = 300
    x = np.random.default_rng(22).standard_normal(n)
    xs = x / np.std(x)
    fit = fit_arma(x, 1, 1)
    llf_std = fit.llf + n * math.log(fit.scale)
    model = ExactLikelihood(xs, 1, 1)
    first = optimiser.solve(model, *hannan_rissanen(xs, 1, 1), polish=True)  # short: no warm-up
    llf_first = -0.5 * n * (math.log(2 * math.pi) + 1 + math.log(first.ev.S / n)) - 0.5 * first.ev.D
    assert llf_std > llf_first + 0.5
    ref = sm_fit(xs, 1, 1)
    assert llf_std >= ref.llf - AIC_TOL / 2
    assert near_redundant(fit.ar, fit.ma)


def test_long_record_path(monkeypatch: pytest.MonkeyPatch) -> None:
    """The long-record path - Newton on a presample, then on the whole series; bse from the
    analytic Hessian (relative error ~20/n) - with its thresholds lowered to run at n = 10,000."""
    monkeypatch.setattr(optimiser, "PRESAMPLE", 2_000)
    monkeypatch.setattr(fitmod, "_FD_HESSIAN_MAX_N", 5_000)
    n = 10_000
    x = simulate([1.2, -0.5], [0.4], n, 98, 5.0)
    xs = x / np.std(x)
    fit = fit_arma(x, 2, 1)
    ref = sm_fit(xs, 2, 1, cov_type="approx")
    np.testing.assert_allclose(np.r_[fit.ar, fit.ma], ref.params[:-1], atol=PARAM_TOL)
    assert fit.aic <= ref.aic + 2 * n * math.log(np.std(x)) + AIC_TOL
    ref_bse = np.r_[ref.bse[:-1], ref.bse[-1] * np.std(x) ** 2]
    np.testing.assert_allclose(list(fit.bse.values()), ref_bse, rtol=20 / n)


def test_misleading_d_curvature_falls_back_to_the_plain_newton(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """On long series Newton includes D's curvature; where that makes the line search damp
    three steps in a row below 1/32 the run ends and ``solve`` iterates again without it (on 1e6
    white-noise block means one ARMA(2,1) start took 100 iterations of ~30 halvings
    otherwise).  Forcing the give-up on every step must reach the same optimum: AIC within
    1e-3 and parameters within 1e-4 (the stopping rule's absolute step is 1e-6)."""
    from scipy.signal import lfilter

    e = np.random.default_rng(21).standard_normal(4 * optimiser.PRESAMPLE + 50_000)
    x = lfilter([1.0, 0.4], [1.0, -0.5], e)  # ARMA(1,1), phi 0.5, theta 0.4
    usual = fit_arma(x, 1, 1, mean=True)
    monkeypatch.setattr(optimiser, "_HD_GIVE_UP_STEP", 2.0)  # every step "too damped"
    monkeypatch.setattr(optimiser, "_HD_GIVE_UP_RUN", 1)  # and the first one ends the run
    fallback = fit_arma(x, 1, 1, mean=True)
    assert usual.converged and fallback.converged
    assert abs(fallback.aic - usual.aic) < 1e-3
    for name, value in usual.params.items():
        assert fallback.params[name] == pytest.approx(value, abs=1e-4), name


def test_starts_that_warm_up_alike_share_the_whole_series_run(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """On long series each extra start of a redundant fit first runs on the presample and the
    prefix; one that ends where an earlier start did is not iterated on the whole series
    again.  The fit must equal the one that iterates every start (thresholds lowered to run
    at n = 40,000; AIC within 1e-3, parameters within 1e-4: the stopping rule's step)."""
    monkeypatch.setattr(optimiser, "PRESAMPLE", 2_000)
    monkeypatch.setattr(optimiser, "PREFIXES", (8_000,))
    x = np.random.default_rng(5).standard_normal(40_000)   # ARMA(1,1) is redundant here
    runs: list[int] = []
    solve = optimiser.solve

    def counted(*args: object, **kw: object) -> optimiser.NewtonResult:
        runs.append(1)
        return solve(*args, **kw)  # type: ignore[arg-type]

    monkeypatch.setattr(optimiser, "solve", counted)
    shared = fit_arma(x, 1, 1, mean=True)
    n_shared = len(runs)
    monkeypatch.setattr(optimiser, "_SAME_START", 0.0)     # every start runs
    runs.clear()
    every = fit_arma(x, 1, 1, mean=True)
    assert n_shared < len(runs)
    assert abs(shared.aic - every.aic) < 1e-3
    for name, value in every.params.items():
        assert shared.params[name] == pytest.approx(value, abs=1e-4), name


def test_a_start_that_warms_up_alike_stops_at_that_stage(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """A start whose presample stage ends where a known path's did (within 1e-3) is not run
    on the prefixes: the rest of its warm-up would repeat that path's."""
    monkeypatch.setattr(optimiser, "PRESAMPLE", 2_000)
    monkeypatch.setattr(optimiser, "PREFIXES", (8_000,))
    x = simulate([0.6], [0.3], 40_000, 6, 1.0)
    xs = (x - x.mean()) / x.std()
    model = ExactLikelihood(xs, 1, 1, mean=True)
    start = (np.array([0.5]), np.array([0.2]))
    known = optimiser.warm_start(xs, model, *start)
    assert known is not None and len(known) == 3
    sizes: list[int] = []
    newton = optimiser.newton

    def counted(m: ExactLikelihood, *args: object, **kw: object) -> optimiser.NewtonResult:
        sizes.append(m.n)
        return newton(m, *args, **kw)  # type: ignore[arg-type]

    monkeypatch.setattr(optimiser, "newton", counted)
    assert optimiser.warm_start(xs, model, *start, known=[known]) is None
    assert sizes == [2_000]           # the presample stage only
    sizes.clear()
    other = [*known[:1], (np.array([-0.9]), np.array([0.0])), *known[2:]]
    optimiser.warm_start(xs, model, *start, known=[other])
    assert sizes == [2_000, 8_000]    # another presample end: every stage


def test_a_run_stopped_at_a_unit_root_is_not_repeated(monkeypatch: pytest.MonkeyPatch) -> None:
    """The restricted likelihood of a random walk rises to the unit AR root: Newton stops
    there (``at_unit_root``) and ``solve`` does not iterate again without D's curvature (that
    retry is for steps D's curvature damped)."""
    monkeypatch.setattr(optimiser, "PRESAMPLE", 2_000)
    x = np.cumsum(np.random.default_rng(8).standard_normal(20_000))
    xs = (x - x.mean()) / x.std()
    model = ExactLikelihood(xs, 1, 1, mean=True)
    calls: list[bool] = []
    newton = optimiser.newton

    def counted(m: ExactLikelihood, *args: object, **kw: object) -> optimiser.NewtonResult:
        res = newton(m, *args, **kw)  # type: ignore[arg-type]
        if m is model:
            calls.append(res.at_unit_root)
        return res

    monkeypatch.setattr(optimiser, "newton", counted)
    start = optimiser.warm_start(xs, model, np.array([0.9]), np.array([0.0]))
    assert start is not None
    res = optimiser.solve(model, *start[-1], polish=False)
    assert res.at_unit_root and not res.converged
    assert calls == [True]


def test_after_the_last_prefix_the_whole_series_runs_plain_newton(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """A series longer than four times the last prefix starts its whole-series Newton run
    within a few standard errors of the optimum, so the run goes without D's curvature (on
    1e8 samples it saved 16-60 s and reached the same AICs); a shorter one keeps it.  With
    the thresholds lowered to run at n = 40,000 the two policies must reach the same
    optimum (AIC within 1e-3, parameters within 1e-4: the stopping rule's step) and the
    same standard errors, D's curvature included in both."""
    from scipy.signal import lfilter

    monkeypatch.setattr(optimiser, "PRESAMPLE", 2_000)
    monkeypatch.setattr(fitmod, "_FD_HESSIAN_MAX_N", 5_000)  # the long series' analytic SEs
    e = np.random.default_rng(31).standard_normal(40_000)
    x = lfilter([1.0, -0.6], [1.0, -0.995], e)          # ARMA(1,1) near a unit root
    calls: list[bool] = []
    newton = optimiser.newton

    def whole(m: ExactLikelihood, *args: object, **kw: object) -> optimiser.NewtonResult:
        if m.n == x.size:
            calls.append(bool(kw.get("d_curvature")))
        return newton(m, *args, **kw)  # type: ignore[arg-type]

    monkeypatch.setattr(optimiser, "newton", whole)
    monkeypatch.setattr(optimiser, "PREFIXES", (8_000,))          # 40,000 > 4 x 8,000
    plain = fit_arma(x, 1, 1, mean=True)
    assert calls[0] is False
    calls.clear()
    monkeypatch.setattr(optimiser, "PREFIXES", (8_000, 20_000))   # 40,000 <= 4 x 20,000
    curved = fit_arma(x, 1, 1, mean=True)
    assert calls[0] is True
    assert plain.converged and curved.converged
    assert abs(plain.aic - curved.aic) < 1e-3
    for name, value in curved.params.items():
        assert plain.params[name] == pytest.approx(value, abs=1e-4), name
    # both standard errors take D's curvature (the plain run's is added at its optimum):
    # they agree to 4e-8; without D's curvature ar.L1's would be 0.29 % smaller
    for name, value in curved.bse.items():
        assert plain.bse[name] == pytest.approx(value, rel=1e-5), name
