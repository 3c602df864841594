"""Exact Gaussian maximum likelihood of the noise model of a rate record: :func:`fit_noise_ml`.

Why the series and not the Allan curve
    The Allan curve is a summary that loses information (the Allan variance is not a
    sufficient statistic); the efficient estimator of the noise parameters is the maximum
    of the exact likelihood of the record itself.  An :class:`~fogts.allan.result.AllanResult`
    does not carry its series, so this fit is its own entry point, ``fit_noise_ml(rate,
    fs_hz, ...)``, returning the same :class:`~fogts.allan.noise_model.NoiseModel` as
    :func:`~fogts.allan.noise.fit_noise` (``method="ml"``; ``fit_noise(curve,
    method="ml")`` raises an error that names this function).

The model and its likelihood (:mod:`fogts.allan.ml_model`)
    White rate noise (N), a rate random walk (K), bias instability (B) and a ramp (R), all
    continuous-time processes observed as interval means, with an unknown (diffuse) bias.
    The likelihood of the block means (every sample when ``decimate=1``) is exact, by
    statsmodels' Kalman filter (which switches to the steady-state gain once the state
    covariance has converged); with block means of ``L > 1`` samples the within-block
    contrasts add an approximate likelihood that recovers the information on N.
    Quantisation (Q, white angle noise: an MA(1) with a unit root in the rate) is not in
    the model.

Bias instability: a flicker component or free Gauss-Markov terms (``b_model``)
    ``"flicker"``: the Markov sum of :func:`fogts.allan.markov.flicker_poles` (three
    first-order Gauss-Markov poles per decade from ``dt/100`` to ten times the record,
    pole variances ``Delta B^2/pi``, ``Delta = ln(10)/3``; Keshner, "1/f noise",
    *Proc. IEEE* 70(3), 1982, 212-218), one amplitude ``B`` -- flicker's flat Allan
    variance :math:`(2\\ln 2/\\pi)B^2` (IEEE 952 Annex C) within 0.5 % over the data taus;
    poles much shorter than a block enter the block means as white noise
    (:data:`fogts.allan.ml_model.LUMP_SHARE`).  ``"gm"``: ``1..max_gm`` free Gauss-Markov
    terms (variance and correlation time each, at most a quarter of the record), B their
    flicker equivalent (:func:`fogts.allan.gmwm.log_b_equivalent`, at the octave taus of
    the record).  ``"auto"`` fits both and keeps the smaller BIC: free Gauss-Markov terms
    with correlation times inside the record cannot follow a flicker plateau out to the
    longest taus, and their misfit there goes into K (seen: K +24 to +37 % on two tactical
    records, against -9 and -4 % with the flicker component).

Estimation
    The parameters are logs of the variances and correlation times, started from the
    five-term WLS fit of the octave Allan curve (:func:`fogts.allan.noise.fit_noise`) and
    maximised by L-BFGS-B (finite-difference gradients).  Free Gauss-Markov models are
    fitted for ``k = 1, 2, ...`` terms (each from the better of a start spread over the
    WLS fit's bias-instability region and the ``k - 1`` fit with one more term), stopping
    once the BIC (Schwarz 1978, *Ann. Statist.* 6(2), 461-464), :math:`-2\\log L + p\\ln n`,
    grows; the smallest BIC wins.  The standard errors are from the observed information,
    the inverse of the numerical Hessian of :math:`-\\log L` in the log parameters
    (``statsmodels.tools.numdiff.approx_hess3``), carried to N, K, B and the Gauss-Markov
    terms by the delta method; intervals are symmetric on the log scale.  R is the
    filtered (GLS) ramp at the end of the record with its filter variance.

Decimation
    ``decimate="auto"`` uses ``L = ceil(n / max_blocks)`` (default at most 4096 blocks, so
    1e6 samples run in a few seconds); the block length is in ``NoiseModel.ml``.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize
from scipy.stats import norm

from fogts._typing import FloatArray
from fogts._validate import check_choice, check_fraction, check_int, check_positive, to_float_array
from fogts.allan.gmwm import fitted_term, log_b_equivalent
from fogts.allan.gmwm_core import Composite, WvData, model_wv
from fogts.allan.gmwm_result import GaussMarkovTerm
from fogts.allan.ml_model import (
    BlockData,
    Structure,
    block_data,
    conditional_limit,
    final_state,
    log_likelihood,
    observed_cov,
)
from fogts.allan.ml_result import MlSummary
from fogts.allan.noise_input import FitCurve, read_fit_curve
from fogts.allan.noise_model import NoiseModel, NoiseTerm
from fogts.allan.noise_selection import floorless_flicker, identify_terms
from fogts.allan.readoff import readoff_of
from fogts.allan.terms import parse_terms
from fogts.errors import ConvergenceWarning, DataError, UnidentifiableTermWarning
from fogts.units import base_unit_factor, quantity_of

__all__ = ["B_MODELS", "DEFAULT_MAX_BLOCKS", "ML_TERMS", "fit_noise_ml"]

#: Models of bias instability: a Markov-sum flicker, free Gauss-Markov terms, or both.
B_MODELS: tuple[str, ...] = ("auto", "flicker", "gm")

#: Terms the state-space model has (quantisation Q is not in it).
ML_TERMS: tuple[str, ...] = ("N", "B", "K", "R")
#: Most blocks the Kalman filter runs on with ``decimate="auto"``.
DEFAULT_MAX_BLOCKS = 4096
_MIN_BLOCKS = 64
_MAX_GM = 3
#: Longest Gauss-Markov correlation time, as a fraction of the record.
_T_MAX_SHARE = 0.25
_LOG_SPAN = 12.0
#: a_0 = (2 ln 2 / pi) B^2: flicker's Allan variance (IEEE 952 Annex C).
_B_PLATEAU2 = 2 * math.log(2) / math.pi


def fit_noise_ml(rate: FloatArray | Sequence[float], fs_hz: float, *, units: str = "deg/h",
                 axis: str = "", terms: Sequence[str] | str = ("N", "B", "K"),
                 b_model: str = "auto", max_gm: int = _MAX_GM, decimate: int | str = "auto",
                 max_blocks: int = DEFAULT_MAX_BLOCKS, confidence: float = 0.683
                 ) -> NoiseModel:
    """Fit the noise model to a rate record by exact Gaussian maximum likelihood.

    Parameters
    ----------
    rate : array_like
        One axis of rate samples (finite), in ``units``.
    fs_hz : float
        Sample rate (Hz).
    units : str
        Rate unit of ``rate`` (the terms are reported in IEEE 952's degree units).
    axis : str
        Axis name for the result.
    terms : sequence of str or str
        Which of N, B, K, R the model has; B stands for ``1..max_gm`` Gauss-Markov terms.
    b_model : {"auto", "flicker", "gm"}
        How bias instability is modelled (module docstring): ``"flicker"``, a Markov-sum
        flicker of one amplitude B; ``"gm"``, ``1..max_gm`` free Gauss-Markov terms (B is
        their flicker equivalent); ``"auto"``, both, the smaller BIC wins.
    max_gm : int
        Most free Gauss-Markov terms, 1..3.
    decimate : int or "auto"
        Block length ``L`` of the block means (1: every sample; module docstring).
    max_blocks : int
        With ``decimate="auto"``: the most blocks, ``L = ceil(n / max_blocks)``.
    confidence : float
        Level of the intervals, in (0, 1).

    Returns
    -------
    NoiseModel
        ``method="ml"``; ``ml`` holds the model, its Gauss-Markov components, the
        log-likelihood and the decimation; ``tau_s``/``dev`` are the record's octave oadev.

    Raises
    ------
    DataError
        Bad ``rate``, ``fs_hz``, ``terms``, ``max_gm``, ``decimate``, ``max_blocks`` or
        ``confidence``; fewer than 64 blocks.

    Examples
    --------
    >>> import warnings
    >>> from fogts.simulate.gyro import simulate_gyro
    >>> run = simulate_gyro({"N": 0.01, "K": 1.0}, fs_hz=10, duration_s=3000, rng=1)
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")
    ...     model = fit_noise_ml(run.rate, 10.0, terms="N,K")
    >>> model.method, round(model["N"].value, 2), model.ml.decimation
    ('ml', 0.01, 8)
    """
    y = to_float_array(rate, "rate", min_length=2)
    fs = check_positive("fs_hz", fs_hz)
    names = _ml_terms(terms)
    max_gm = check_int("max_gm", max_gm, minimum=1, maximum=_MAX_GM)
    b_model = check_choice("b_model", b_model, B_MODELS)
    confidence = check_fraction("confidence", confidence)
    max_blocks = check_int("max_blocks", max_blocks, minimum=_MIN_BLOCKS)
    L = _block_length(decimate, y.size, max_blocks)
    data = block_data(y, 1.0 / fs, L)
    curve, pilot = _curve(y, fs, units, axis)
    fits = _candidates(names, b_model, max_gm, data, pilot)
    bic = [_bic(f, data) for f in fits]
    best = fits[int(np.argmin(bic))]
    st, theta, ll, converged = best.st, best.theta, best.ll, best.converged
    cov = observed_cov(theta, st, data, theta > best.lower + 1e-3)
    cands = tuple((f.st.label(), b) for f, b in zip(fits, bic, strict=True))
    model = _noise_model(curve, names, st, theta, cov, data, ll, converged, cands, confidence)
    return _zero_terms(model, best, cov, data)


def _ml_terms(terms: Sequence[str] | str) -> tuple[str, ...]:
    names = parse_terms(terms)
    bad = [n for n in names if n not in ML_TERMS]
    if bad:
        raise DataError(f"terms {', '.join(bad)} are not in the maximum-likelihood model "
                        f"(quantisation is not modelled); use terms from "
                        f"{', '.join(ML_TERMS)}, got {terms!r}")
    if not set(names) & {"N", "B", "K"}:
        raise DataError(f"terms must include at least one of N, B, K, got {terms!r}")
    return names


def _block_length(decimate: int | str, n: int, max_blocks: int) -> int:
    if decimate == "auto":
        L = max(1, math.ceil(n / max_blocks))
    elif isinstance(decimate, str):
        raise DataError(f"decimate must be 'auto' or an integer >= 1, got {decimate!r}")
    else:
        L = check_int("decimate", decimate, minimum=1)
    if n // L < _MIN_BLOCKS:
        raise DataError(f"rate has {n} samples, {n // L} blocks of decimate = {L}; the "
                        f"fit needs at least {_MIN_BLOCKS} blocks: use a smaller decimate "
                        "or a longer record")
    return L


def _curve(y: FloatArray, fs: float, units: str, axis: str
           ) -> tuple[FitCurve, dict[str, float]]:
    """The record's octave oadev as a fit curve, and the WLS fit's ``a_n`` (curve units)
    of N, B, K with every term kept (the starting values)."""
    from fogts.allan.api import allan_deviation
    from fogts.allan.noise import fit_noise

    result = allan_deviation(y, fs_hz=fs, taus="octave", units=units)
    curve = read_fit_curve(result)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = fit_noise(result, terms="N,B,K", significance=None)
    pilot = dict(zip(fit.names, fit._a, strict=True))
    return (dataclasses.replace(curve, axis=axis) if axis else curve), pilot


def _start(st: Structure, data: BlockData, pilot: dict[str, float]) -> FloatArray:
    """Starting logs (scaled units): the pilot's N and K, and ``n_gm`` Gauss-Markov terms
    spread over the pilot's bias-instability region, each of variance
    ``Delta a_0 / (2 ln 2)`` for a spacing ``e^Delta`` (the pole weights of a Markov-sum
    flicker, :func:`fogts.allan.markov.flicker_poles`)."""
    s2 = data.scale**2
    dur = data.n_used * data.dt
    a_n = max(pilot["N"], data.dt * s2 * 1e-3) / s2
    a_b = max(pilot["B"], a_n / dur) / s2
    a_k = max(pilot["K"], a_b / dur * 1e-2) / s2
    out = ([math.log(a_n)] if st.white else []) + ([math.log(3 * a_k)] if st.rw else [])
    if st.flicker:
        out.append(math.log(a_b / _B_PLATEAU2))
    if st.n_gm:
        lo = min(max(a_n / a_b, 2 * data.dt), dur * _T_MAX_SHARE / 4)
        hi = min(max(a_b / a_k, 4 * lo), dur * _T_MAX_SHARE)
        t_c = np.geomspace(lo, hi, st.n_gm + 2)[1:-1] / 1.89
        spread = max(math.log(hi / lo) / st.n_gm, math.log(4.0))
        for t in t_c:
            out += [math.log(spread * a_b / (2 * math.log(2))), math.log(float(t))]
    return np.array(out)


def _bounds(st: Structure, theta0: FloatArray, data: BlockData) -> list[tuple[float, float]]:
    b = [(float(v) - _LOG_SPAN, float(v) + _LOG_SPAN) for v in theta0]
    i = st.gm_index
    t_max = math.log(data.n_used * data.dt * _T_MAX_SHARE)
    for j in range(st.n_gm):
        b[i + 2 * j + 1] = (math.log(data.dt), t_max)
    return b


@dataclass(frozen=True)
class _Fit:
    st: Structure
    theta: FloatArray
    ll: float
    converged: bool
    lower: FloatArray


def _candidates(names: tuple[str, ...], b_model: str, max_gm: int, data: BlockData,
                pilot: dict[str, float]) -> list[_Fit]:
    """Every model fitted: the flicker model and/or the Gauss-Markov sequence."""
    base = Structure("N" in names, "K" in names, 0, "R" in names)
    if "B" not in names:
        return [_fit(base, data, [_start(base, data, pilot)])]
    fits = []
    if b_model in ("auto", "flicker"):
        st = dataclasses.replace(base, flicker=_flicker_poles(data))
        fits.append(_fit(st, data, [_start(st, data, pilot)]))
    if b_model in ("auto", "gm"):
        fits += _fit_sequence(base, max_gm, data, pilot)
    return fits


def _flicker_poles(data: BlockData) -> tuple[tuple[float, float], ...]:
    """The poles ``(T_i, w_i)`` of the Markov-sum flicker over this record, ``w_i =
    q_i^2 T_i / 2`` per unit B^2 (:func:`fogts.allan.markov.flicker_poles`: three
    per decade, Keshner 1982)."""
    from fogts.allan.markov import flicker_poles

    t, q = flicker_poles(1.0 / data.dt, data.n_used * data.dt)
    return tuple((float(ti), float(qi**2 * ti / 2)) for ti, qi in zip(t, q, strict=True))


def _fit_sequence(base: Structure, max_gm: int, data: BlockData, pilot: dict[str, float]
                  ) -> list[_Fit]:
    """Fits with ``1..max_gm`` Gauss-Markov terms, stopping once
    the BIC grows; each from the better of the pilot start and the previous fit with one
    more term in its widest gap of correlation times."""
    fits: list[_Fit] = []
    for k in range(1, max_gm + 1):
        st = dataclasses.replace(base, n_gm=k)
        starts = [_start(st, data, pilot)]
        if fits:
            starts.append(_add_gm(fits[-1], data, pilot))
        fits.append(_fit(st, data, starts))
        if k > 1 and _bic(fits[-1], data) > _bic(fits[-2], data):
            break
    return fits


def _bic(fit: _Fit, data: BlockData) -> float:
    return -2 * fit.ll + fit.st.n_params * math.log(data.n_used)


def _add_gm(prev: _Fit, data: BlockData, pilot: dict[str, float]) -> FloatArray:
    """``prev``'s parameters with one more Gauss-Markov term, in the widest gap (on the
    log scale) of its correlation times within the bounds, of the mean variance."""
    i0 = prev.st.gm_index
    logs_t = np.sort(prev.theta[i0 + 1::2])
    edges = np.concatenate([[math.log(2 * data.dt)], logs_t,
                            [math.log(data.n_used * data.dt * _T_MAX_SHARE)]])
    gap = int(np.argmax(np.diff(edges)))
    log_s2 = float(np.mean(prev.theta[i0::2]))
    return np.concatenate([prev.theta, [log_s2, 0.5 * (edges[gap] + edges[gap + 1])]])


def _fit(st: Structure, data: BlockData, starts: list[FloatArray]) -> _Fit:
    """Maximise the log-likelihood of one structure from the best of ``starts``."""

    def nll(theta: FloatArray) -> float:
        return -log_likelihood(theta, st, data) / data.n_blocks

    bounds = _bounds(st, starts[0], data)
    lo, hi = [b[0] for b in bounds], [b[1] for b in bounds]
    starts = [np.clip(s, lo, hi) for s in starts]
    theta0 = min(starts, key=nll) if len(starts) > 1 else starts[0]
    res = minimize(nll, theta0, method="L-BFGS-B", bounds=bounds,
                   options={"maxiter": 200, "ftol": 1e-10, "gtol": 1e-6})
    theta = np.asarray(res.x, dtype=np.float64)
    return _Fit(st, theta, -float(res.fun) * data.n_blocks, bool(res.success),
                np.array(lo, dtype=np.float64))


def _wv_data(curve: FitCurve, data: BlockData) -> WvData:
    return WvData(curve.tau, np.zeros_like(curve.tau), 1.0, data.dt, data.n_used,
                  np.zeros((0, 0)))


def _gmwm_theta(theta: FloatArray, st: Structure, data: BlockData
                ) -> tuple[FloatArray, Composite]:
    """The parameters as a GMWM composite (``log a_n`` of N, K and the flicker B, then
    log s2, log T) in the curve's units squared (``a_n`` of flicker: its Allan plateau,
    the ripple of the pole sum left out)."""
    ls2 = 2 * math.log(data.scale)
    out, powers, i = [], [], 0
    if st.white:
        out.append(theta[0] + ls2)
        powers.append(-1)
        i = 1
    if st.rw:
        out.append(theta[i] - math.log(3.0) + ls2)  # a_1 = k^2 / 3
        powers.append(1)
        i += 1
    if st.flicker:
        out.append(theta[i] + math.log(_B_PLATEAU2) + ls2)
        powers.append(0)
    for j in range(st.n_gm):
        out += [theta[i + 2 * j] + ls2, theta[i + 2 * j + 1]]
    return np.array(out, dtype=np.float64), Composite(tuple(powers), st.n_gm)


def _term_logs(theta: FloatArray, cov: FloatArray, st: Structure, data: BlockData,
               wv: WvData) -> dict[str, tuple[float, float]]:
    """``log a_n`` (curve units) and its standard error of N, K and the B equivalent."""
    g_theta, comp = _gmwm_theta(theta, st, data)
    out: dict[str, tuple[float, float]] = {}
    for name, p in (("N", -1), ("B", 0), ("K", 1)):
        if p in comp.powers:
            i = comp.powers.index(p)
            out[name] = (float(g_theta[i]), math.sqrt(max(float(cov[i, i]), 0.0)))
    if st.n_gm:
        grad = _gradient(lambda t: log_b_equivalent(_gmwm_theta(t, st, data)[0], comp, wv),
                         theta)
        out["B"] = (log_b_equivalent(g_theta, comp, wv),
                    math.sqrt(max(float(grad @ cov @ grad), 0.0)))
    return out


def _gradient(f: Callable[[FloatArray], float], x: FloatArray, step: float = 1e-5
              ) -> FloatArray:
    g = np.zeros(x.size)
    for i in range(x.size):
        e = np.zeros(x.size)
        e[i] = step
        g[i] = (f(x + e) - f(x - e)) / (2 * step)
    return g


def _drift_term(st: Structure, theta: FloatArray, data: BlockData, factor: float, z: float,
                quantity: str) -> NoiseTerm:
    """R from the filtered ramp: ``a_2 = r^2 / 2``."""
    state, pcov = final_state(theta, st, data)
    r = abs(float(state[1])) * data.scale
    se_r = math.sqrt(max(float(pcov[1, 1]), 0.0)) * data.scale
    if r == 0.0:
        r = 1e-300
    return fitted_term("R", math.log(r * r / 2), 2 * se_r / r, 1.0, factor, z, quantity)


def _gm_terms(theta: FloatArray, cov: FloatArray, st: Structure, data: BlockData,
              factor: float) -> tuple[GaussMarkovTerm, ...]:
    i0 = st.gm_index
    out = []
    for j in range(st.n_gm):
        i = i0 + 2 * j
        sigma = math.sqrt(math.exp(theta[i])) * data.scale * factor
        t_c = math.exp(theta[i + 1])
        se_s = math.sqrt(max(float(cov[i, i]), 0.0)) / 2
        se_t = math.sqrt(max(float(cov[i + 1, i + 1]), 0.0))
        out.append(GaussMarkovTerm(sigma, sigma * se_s, t_c, t_c * se_t))
    return tuple(sorted(out, key=lambda g: g.t_c))


def _zero_terms(model: NoiseModel, fit: _Fit, cov: FloatArray, data: BlockData
                ) -> NoiseModel:
    """N, K or a flicker B whose variance ended at the optimiser's lower bound, or where
    the likelihood has no curvature in it (no positive variance in ``cov``: the
    likelihood is flat towards zero): value 0, ``at_bound``, and as the interval's upper
    end the conditional likelihood-ratio bound at the model's confidence."""
    st, z = fit.st, float(norm.ppf(0.5 + model.confidence / 2))
    index = {"N": 0, "K": int(st.white), "B": int(st.white) + int(st.rw)}
    present = {"N": st.white, "K": st.rw, "B": bool(st.flicker)}
    terms, a_out = list(model.terms), list(model._a)
    for j, term in enumerate(terms):
        i = index.get(term.name, -1)
        if i < 0 or not present[term.name] or (fit.theta[i] > fit.lower[i] + 1e-3
                                                and cov[i, i] > 0):
            continue
        log_hi = conditional_limit(fit.theta, i, st, data, z)
        ratio = math.sqrt(math.exp(log_hi - fit.theta[i]))   # C_hi / C at the bound
        terms[j] = dataclasses.replace(
            term, value=0.0, stderr=math.nan, ci_low=0.0, ci_high=term.value * ratio,
            c_coeff=0.0, c_stderr=math.nan, at_bound=True, z_score=0.0)
        a_out[j] = 0.0
    return dataclasses.replace(model, terms=tuple(terms), _a=tuple(a_out))


def _noise_model(curve: FitCurve, names: tuple[str, ...], st: Structure, theta: FloatArray,
                 cov: FloatArray, data: BlockData, ll: float, converged: bool,
                 cands: tuple[tuple[str, float], ...], confidence: float) -> NoiseModel:
    quantity, factor = quantity_of(curve.units), base_unit_factor(curve.units)
    z = float(norm.ppf(0.5 + confidence / 2))
    wv = _wv_data(curve, data)
    logs = _term_logs(theta, cov, st, data, wv)
    terms = [fitted_term(n, *logs[n], 1.0, factor, z, quantity) for n in names if n in logs]
    if "R" in names:
        terms.append(_drift_term(st, theta, data, factor, z, quantity))
    order = {n: i for i, n in enumerate(ML_TERMS)}
    terms.sort(key=lambda t: order[t.name])
    a_out = tuple((t.c_coeff / factor) ** 2 for t in terms)
    g_theta, comp = _gmwm_theta(theta, st, data)
    fitted = 2 * model_wv(g_theta, comp, wv) + (
        a_out[[t.name for t in terms].index("R")] * curve.tau**2 if "R" in names else 0.0)
    ll_units = ll - data.n_used * math.log(data.scale)
    stderr = "observed information (numerical Hessian of the log-likelihood)"
    summary = MlSummary(
        model=st.label(), gauss_markov=_gm_terms(theta, cov, st, data, factor),
        log_likelihood=ll_units, n_params=st.n_params, decimation=data.L,
        block_s=data.delta, n_blocks=data.n_blocks, n_used=data.n_used, candidates=cands,
        converged=converged, stderr=stderr)
    model = NoiseModel(
        terms=tuple(terms), confidence=confidence, method="ml", kind=curve.kind,
        units=curve.units, axis=curve.axis, deg_per_hour_factor=factor, tau_s=curve.tau,
        dev=curve.dev, fitted_dev=np.sqrt(fitted), weight=np.ones_like(curve.tau),
        edf=curve.edf, edf_source=curve.edf_source, chi2=math.nan, dof=math.nan,
        model_error=math.nan, stderr_method=stderr, iterations=0, converged=converged,
        readoff=readoff_of(curve, factor, quantity),
        excluded_tau_s=tuple(curve.excluded), significance=None, _a=a_out,
        quantity=quantity, ml=summary)
    issued = []
    identified, messages = identify_terms(model, curve.tau)
    identified, floor_message = floorless_flicker(dataclasses.replace(model, terms=identified))
    if floor_message:
        messages.append(floor_message)
    for message in messages:
        issued.append(message)
        warnings.warn(message, UnidentifiableTermWarning, stacklevel=3)
    if not converged:
        issued.append("the ML optimiser did not converge")
        warnings.warn(issued[-1], ConvergenceWarning, stacklevel=3)
    return dataclasses.replace(model, terms=identified, warnings=tuple(issued))
