"""Kalman filtering and smoothing of a gyro series with an ARMA drift model (seed 004, step 3).

The ARMA(p, q) drift (statsmodels sign convention, DESIGN.md)

    x_t = φ₁x_{t-1} + … + φ_p x_{t-p} + a_t + θ₁a_{t-1} + … + θ_q a_{t-q},   a_t ~ N(0, σ²)

observed with white measurement noise, y_t = x_t + ε_t, ε_t ~ N(0, H), is written in
Harvey's state-space form (Harvey, *Forecasting, Structural Time Series Models and the Kalman
Filter*, 1989, §3.4; Durbin & Koopman, *Time Series Analysis by State Space Methods*, 2nd ed.,
2012, §3.4), with r = max(p, q + 1):

    α_{t+1} = T α_t + R a_{t+1},  y_t = Z α_t + ε_t,
    T = [φ | I_{r-1}; 0],  R = (1, θ₁, …, θ_{r-1})',  Z = (1, 0, …, 0),

and filtered with statsmodels' state-space machinery (``MLEModel``, stationary
initialisation).  Outputs are the *filtered* signal Z a_{t|t} = E[x_t | y_1..y_t], the
*smoothed* signal E[x_t | y_1..y_n] and the one-step *predictions* Z a_t = E[y_t | y_1..y_{t-1}].

Long records: once the Riccati recursion has converged the gain is constant, and the filter
is a fixed linear system.  fogts then solves the discrete algebraic Riccati equation
(``scipy.linalg.solve_discrete_are``) for the steady predicted covariance P, runs statsmodels'
exact filter only over the transient, and continues with ``scipy.signal.lfilter``; the
smoother uses the steady backward recursion r_{t-1} = Z'F⁻¹v_t + L'r_t, α̂_t = a_t + P r_{t-1}
(Durbin & Koopman eq. 4.44) and the exact time-varying recursion over the transient.  The
result equals the exact filter to the Riccati convergence tolerance (1e-12 relative).

``measurement_noise="estimate"`` maximises the likelihood over H with the ARMA parameters
fixed (bounded 1-D search on log(H/σ²)).  When the ARMA model was fitted to the same noisy
observations, its σ² already contains the white noise, the estimate goes to H = 0 and the
filter follows the data; the result says so.  Give H explicitly (for example the white
noise N² fs of the Allan analysis) to smooth in that case.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Literal, get_args

import numpy as np
import pandas as pd
from scipy import linalg, optimize, signal

from fogts._typing import FloatArray
from fogts._validate import check_choice, check_positive, pandas_index, to_float_array
from fogts.arma.fit import model_name
from fogts.arma.spec import ArmaSpec
from fogts.errors import DataError

__all__ = ["KALMAN_METHODS", "MODEL_CHOICES", "ArmaStateSpace", "KalmanResult", "arma_kalman",
           "arma_state_space", "resolve_arma_model"]

KalmanMethod = Literal["auto", "exact", "steady-state"]
KALMAN_METHODS: tuple[str, ...] = get_args(KalmanMethod)
#: Relative convergence tolerance of the Riccati recursion for the steady-state switch.
RICCATI_RTOL = 1e-12
#: ``method="auto"`` uses the steady-state filter from this many samples on.
STEADY_STATE_MIN_N = 5000
#: Search range of log10(H / sigma2) when estimating the measurement noise.
LOG_RATIO_BOUNDS = (-10.0, 4.0)
#: Fewest samples filtered.
MIN_KALMAN_SAMPLES = 10
#: An estimated H below this fraction of sigma2 is reported as negligible.
NEGLIGIBLE_H_RATIO = 1e-3
#: Model names accepted by :func:`resolve_arma_model` (and ``fogts filter --model``).
MODEL_CHOICES: tuple[str, ...] = ("auto", "AR(1)", "AR(2)", "AR(3)", "ARMA(1,1)", "ARMA(2,1)")
_ORDERS = {"AR(1)": (1, 0), "AR(2)": (2, 0), "AR(3)": (3, 0), "ARMA(1,1)": (1, 1),
           "ARMA(2,1)": (2, 1)}


def resolve_arma_model(x: Any, spec: str) -> Any:
    """Fit the drift model named by ``spec`` to ``x`` (demeaned first).

    ``"auto"`` runs the candidate selection of :func:`fogts.arma.select.select_arma` and
    returns its best candidate; ``"AR(1)"`` .. ``"ARMA(2,1)"`` fit that order with
    :func:`fogts.arma.fit.fit_arma`.

    Raises
    ------
    DataError
        ``spec`` is not one of :data:`MODEL_CHOICES`.
    """
    check_choice("model", spec, MODEL_CHOICES)
    arr = to_float_array(x, "x", min_length=MIN_KALMAN_SAMPLES)
    arr = arr - float(np.mean(arr))
    if spec == "auto":
        from fogts.arma.select import select_arma

        return select_arma(arr).best
    from fogts.arma.fit import fit_arma

    p, q = _ORDERS[spec]
    return fit_arma(arr, p, q)


# --------------------------------------------------------------------------- model in
@dataclass(frozen=True)
class ArmaStateSpace:
    """Harvey state-space matrices of an ARMA(p, q) model.

    Attributes
    ----------
    ar, ma : ndarray
        φ and θ (statsmodels sign).
    sigma2 : float
        Innovation variance.
    T, R, Z : ndarray
        Transition (r×r), selection (r×1) and design (1×r) matrices.
    name : str
        ``"AR(p)"``, ``"ARMA(p,q)"``...
    """

    ar: FloatArray
    ma: FloatArray
    sigma2: float
    T: FloatArray = field(repr=False)
    R: FloatArray = field(repr=False)
    Z: FloatArray = field(repr=False)
    name: str = ""

    @property
    def k_states(self) -> int:
        return int(self.T.shape[0])


def arma_state_space(model: Any) -> ArmaStateSpace:
    """Harvey state-space form of an ARMA model (see the module docstring).

    Parameters
    ----------
    model : ArmaFit, Selection, Candidate or mapping
        Anything that carries φ, θ and σ² (``{"ar.L1": 0.9, "sigma2": 1.0}`` works).

    Raises
    ------
    DataError
        Non-stationary AR part, non-positive σ², or an unrecognised model.

    Examples
    --------
    >>> ss = arma_state_space({"ar.L1": 0.5, "ar.L2": 0.2, "ma.L1": 0.3, "sigma2": 1.0})
    >>> ss.T.tolist(), ss.R.ravel().tolist()
    ([[0.5, 1.0], [0.2, 0.0]], [1.0, 0.3])
    """
    spec = ArmaSpec.from_any(model)
    ar, ma, sigma2 = np.asarray(spec.ar, float), np.asarray(spec.ma, float), spec.sigma2
    if ar.size:
        roots = np.roots(np.r_[1.0, -ar][::-1])
        if roots.size and np.min(np.abs(roots)) <= 1.0 + 1e-10:
            raise DataError(f"the AR part {ar.tolist()} is not stationary (a root of "
                            "1 - Σφ_i z^i lies on or inside the unit circle); the Kalman filter "
                            "needs a stationary model")
    p, q = ar.size, ma.size
    r = max(p, q + 1)
    T = np.zeros((r, r))
    T[:p, 0] = ar
    if r > 1:
        T[:-1, 1:] = np.eye(r - 1)
    R = np.zeros((r, 1))
    R[0, 0] = 1.0
    R[1:q + 1, 0] = ma
    Z = np.zeros((1, r))
    Z[0, 0] = 1.0
    return ArmaStateSpace(ar=ar, ma=ma, sigma2=sigma2, T=T, R=R, Z=Z, name=model_name(p, q))


def _mle_model(y: FloatArray, ss: ArmaStateSpace, h: float) -> Any:
    """statsmodels ``MLEModel`` with the Harvey matrices and measurement variance ``h``."""
    from statsmodels.tsa.statespace.mlemodel import MLEModel

    mod = MLEModel(y, k_states=ss.k_states, k_posdef=1, initialization="stationary")
    mod["design"] = ss.Z
    mod["transition"] = ss.T
    mod["selection"] = ss.R
    mod["state_cov"] = np.array([[ss.sigma2]])
    mod["obs_cov"] = np.array([[h]])
    return mod


# --------------------------------------------------------------------------- steady state
def _steady(ss: ArmaStateSpace, h: float) -> tuple[FloatArray, float, FloatArray]:
    """Steady predicted covariance P (DARE), innovation variance F, filtered gain K_f."""
    h_eff = max(h, 1e-12 * ss.sigma2)  # the DARE needs a non-singular R
    q = ss.sigma2 * (ss.R @ ss.R.T)
    P = linalg.solve_discrete_are(ss.T.T, ss.Z.T, q, np.array([[h_eff]]))
    P = 0.5 * (P + P.T)
    F = float((ss.Z @ P @ ss.Z.T)[0, 0]) + h
    Kf = (P @ ss.Z.T) / F
    return P, F, Kf


def _riccati_transient(ss: ArmaStateSpace, h: float, P_inf: FloatArray, limit: int) -> int | None:
    """Steps until the exact predicted covariance (stationary start) is within
    RICCATI_RTOL of the DARE solution; None if not within ``limit``."""
    from statsmodels.tsa.statespace.tools import solve_discrete_lyapunov

    P = solve_discrete_lyapunov(ss.T, ss.sigma2 * (ss.R @ ss.R.T))
    scale = float(np.max(np.abs(P_inf))) or 1.0
    q = ss.sigma2 * (ss.R @ ss.R.T)
    for t in range(limit):
        if float(np.max(np.abs(P - P_inf))) <= RICCATI_RTOL * scale:
            return t
        F = float((ss.Z @ P @ ss.Z.T)[0, 0]) + h
        if F <= 0:
            return None
        K = ss.T @ P @ ss.Z.T / F
        L = ss.T - K @ ss.Z
        P = ss.T @ P @ L.T + q
    return None


def _lti(A: FloatArray, B: FloatArray, C: FloatArray, D: FloatArray, u: FloatArray,
         x0: FloatArray | None = None) -> FloatArray:
    """Outputs (n, p) of x_{k+1} = A x_k + B u_k, y_k = C x_k + D u_k for a scalar input,
    via per-output transfer functions and ``scipy.signal.lfilter``."""
    n = u.size
    p = C.shape[0]
    out = np.empty((n, p))
    num, den = signal.ss2tf(A, B.reshape(-1, 1), C, D.reshape(-1, 1))
    for i in range(p):
        out[:, i] = signal.lfilter(num[i], den, u)
    if x0 is not None and np.any(x0 != 0):
        # zero-input response y_k = C A^k x0 = impulse response of (A, x0, C, 0) one step later
        num0, den0 = signal.ss2tf(A, x0.reshape(-1, 1), C, np.zeros((p, 1)))
        imp = np.zeros(n + 1)
        imp[0] = 1.0
        for i in range(p):
            out[:, i] += signal.lfilter(num0[i], den0, imp)[1:]
    return out


# --------------------------------------------------------------------------- result
@dataclass(frozen=True)
class KalmanResult:
    """Kalman filter and smoother output for an ARMA drift model.

    Attributes
    ----------
    observed, filtered, smoothed, predicted : ndarray or pandas.Series
        The input; E[x_t | y_..t]; E[x_t | all y]; E[y_t | y_..t-1].  Same index as the input.
    innovations : ndarray
        y_t - predicted_t.
    model : str
        Model name, e.g. ``"ARMA(2,1)"``.
    ar, ma : tuple of float
    sigma2 : float
        Drift innovation variance.
    measurement_noise : float
        H, the white measurement-noise variance used.
    measurement_noise_source : str
        ``"estimated"`` or ``"given"``.
    method : str
        ``"exact"`` or ``"steady-state"`` (what was run).
    n_transient : int
        Samples filtered exactly before switching to the steady gain (n for ``"exact"``).
    steady_gain : tuple of float
        Steady filtered gain K_f = P Z'/F.
    innovation_variance : float
        Steady F = Z P Z' + H.
    loglike : float
        Gaussian log-likelihood of the observations under the model.
    mean : float
        Mean removed before filtering and added back (0 if ``demean=False``).
    notes : tuple of str
    """

    observed: Any = field(repr=False)
    filtered: Any = field(repr=False)
    smoothed: Any = field(repr=False)
    predicted: Any = field(repr=False)
    innovations: FloatArray = field(repr=False)
    model: str
    ar: tuple[float, ...]
    ma: tuple[float, ...]
    sigma2: float
    measurement_noise: float
    measurement_noise_source: str
    method: str
    n_transient: int
    steady_gain: tuple[float, ...]
    innovation_variance: float
    loglike: float
    mean: float
    notes: tuple[str, ...] = ()

    @property
    def n(self) -> int:
        return int(np.asarray(self.observed).size)

    def to_frame(self) -> pd.DataFrame:
        """Columns observed, filtered, smoothed, predicted (input index kept)."""
        index = self.observed.index if isinstance(self.observed, pd.Series) else None
        return pd.DataFrame({"observed": np.asarray(self.observed),
                             "filtered": np.asarray(self.filtered),
                             "smoothed": np.asarray(self.smoothed),
                             "predicted": np.asarray(self.predicted)}, index=index)

    def variance_reduction(self) -> dict[str, float]:
        """Sample variance of the observed, filtered and smoothed series."""
        return {k: float(np.var(np.asarray(getattr(self, k)), ddof=1))
                for k in ("observed", "filtered", "smoothed")}

    def to_dict(self) -> dict[str, Any]:
        return {"model": self.model, "ar": list(self.ar), "ma": list(self.ma),
                "sigma2": self.sigma2, "measurement_noise": self.measurement_noise,
                "measurement_noise_source": self.measurement_noise_source,
                "method": self.method, "n": self.n, "n_transient": self.n_transient,
                "steady_gain": list(self.steady_gain),
                "innovation_variance": self.innovation_variance, "loglike": self.loglike,
                "mean": self.mean, "variance": self.variance_reduction(),
                "notes": list(self.notes)}

    def summary(self) -> str:
        v = self.variance_reduction()
        how = ("exact" if self.method == "exact" else
               f"steady-state gain after an exact transient of {self.n_transient} samples")
        lines = [f"Kalman filter, {self.model} drift + white measurement noise, n = {self.n} "
                 f"({how})",
                 f"  sigma2 = {self.sigma2:.6g}  H = {self.measurement_noise:.6g} "
                 f"({self.measurement_noise_source})  steady gain = "
                 + ", ".join(f"{g:.4g}" for g in self.steady_gain),
                 f"  std: observed {math.sqrt(v['observed']):.6g}  filtered "
                 f"{math.sqrt(v['filtered']):.6g}  smoothed {math.sqrt(v['smoothed']):.6g}",
                 f"  log-likelihood {self.loglike:.6f}"]
        lines += [f"  note: {n}" for n in self.notes]
        return "\n".join(lines)


# --------------------------------------------------------------------------- filtering
@dataclass
class _Run:
    filtered: FloatArray
    smoothed: FloatArray
    predicted: FloatArray
    innov: FloatArray
    loglike: float
    n0: int


def _exact(y: FloatArray, ss: ArmaStateSpace, h: float, smooth: bool) -> _Run:
    mod = _mle_model(y, ss, h)
    res = mod.smooth([], return_ssm=True) if smooth else mod.filter([], return_ssm=True)
    filt = (ss.Z @ res.filtered_state)[0]
    pred = np.asarray(res.forecasts[0], dtype=float)
    sm = (ss.Z @ res.smoothed_state)[0] if smooth else np.full(y.size, np.nan)
    ll = float(np.sum(res.llf_obs))
    return _Run(filt, sm, pred, np.asarray(res.forecasts_error[0], float), ll, y.size)


def _steady_run(y: FloatArray, ss: ArmaStateSpace, h: float, n0: int, smooth: bool) -> _Run:
    P, F, Kf = _steady(ss, h)
    Z, T = ss.Z, ss.T
    r = ss.k_states
    n = y.size
    # exact filter over the transient (statsmodels); its last predicted state seeds the rest
    filt = np.empty(n)
    pred = np.empty(n)
    innov = np.empty(n)
    ll = 0.0
    a0 = np.zeros(r)
    ex = None
    if n0 > 0:
        mod = _mle_model(y[:n0], ss, h)
        ex = mod.filter([], return_ssm=True)
        filt[:n0] = (Z @ ex.filtered_state)[0]
        pred[:n0] = ex.forecasts[0]
        innov[:n0] = ex.forecasts_error[0]
        ll += float(np.sum(ex.llf_obs))
        a0 = np.asarray(ex.predicted_state[:, n0], dtype=float)
    # steady forward system: state a_t (predicted); outputs [a_{t|t} (r), Z a_t]
    IKZ = np.eye(r) - Kf @ Z
    A = T @ IKZ
    B = (T @ Kf).ravel()
    C = np.vstack([IKZ, Z])
    D = np.r_[Kf.ravel(), 0.0]
    out = _lti(A, B, C, D, y[n0:], a0)
    a_filt = out[:, :r]
    pred[n0:] = out[:, r]
    filt[n0:] = a_filt[:, 0]
    v = y[n0:] - pred[n0:]
    innov[n0:] = v
    ll += float(-0.5 * (v.size * math.log(2.0 * math.pi * F) + np.sum(v * v) / F))
    smoothed = np.full(n, np.nan)
    if smooth:
        # steady backward pass: q_t = Z'v_t/F + L'q_{t+1}, q_n = 0 (reversed-time LTI)
        K = T @ P @ Z.T / F
        L = T - K @ Z
        qs = _lti(L.T, (Z.T / F).ravel(), L.T, (Z.T / F).ravel(), v[::-1])[::-1]
        a_pred_signal = pred[n0:]
        smoothed[n0:] = a_pred_signal + (Z @ P @ qs.T)[0]
        if n0 > 0 and ex is not None:
            q = qs[0].copy()
            # q_{n0} is qs[0]; continue exactly for t = n0-1 .. 0
            q_next = q
            for t in range(n0 - 1, -1, -1):
                Pt = np.asarray(ex.predicted_state_cov[:, :, t], dtype=float)
                Ft = float(ex.forecasts_error_cov[0, 0, t])
                vt = float(ex.forecasts_error[0, t])
                Kt = T @ Pt @ Z.T / Ft
                Lt = T - Kt @ Z
                q_t = (Z.T / Ft).ravel() * vt + Lt.T @ q_next
                at = np.asarray(ex.predicted_state[:, t], dtype=float)
                smoothed[t] = float((Z @ (at + Pt @ q_t))[0])
                q_next = q_t
    return _Run(filt, smoothed, pred, innov, ll, n0)


def _loglike_steady(y: FloatArray, ss: ArmaStateSpace, h: float) -> float:
    """Steady-state (prediction-error) log-likelihood; used to estimate H on long records."""
    _, F, Kf = _steady(ss, h)
    r = ss.k_states
    IKZ = np.eye(r) - Kf @ ss.Z
    pred = _lti(ss.T @ IKZ, (ss.T @ Kf).ravel(), ss.Z, np.zeros(1), y)[:, 0]
    v = y - pred
    return float(-0.5 * (y.size * math.log(2.0 * math.pi * F) + np.sum(v * v) / F))


def _estimate_h(y: FloatArray, ss: ArmaStateSpace, use_steady: bool) -> tuple[float, bool]:
    def nll(u: float) -> float:
        h = ss.sigma2 * 10.0 ** u
        if use_steady:
            return -_loglike_steady(y, ss, h)
        return -float(_mle_model(y, ss, h).loglike([]))

    lo, hi = LOG_RATIO_BOUNDS
    res = optimize.minimize_scalar(nll, bounds=(lo, hi), method="bounded",
                                   options={"xatol": 1e-4})
    u = float(res.x)
    at_lower = u <= lo + 0.05 and nll(lo) <= nll(u) + 1e-9
    return (0.0 if at_lower else ss.sigma2 * 10.0 ** u), at_lower


def arma_kalman(
    x: Any,
    model: Any,
    *,
    measurement_noise: Literal["estimate"] | float = "estimate",
    method: KalmanMethod = "auto",
    smooth: bool = True,
    demean: bool = True,
) -> KalmanResult:
    """Filter and smooth a series with an ARMA drift model plus white measurement noise.

    Parameters
    ----------
    x : array_like or pandas.Series
        Observations (for seed 004: the EMD "rest" of the gyro output).
    model : ArmaFit, Selection, Candidate or mapping
        The drift model (φ, θ, σ² in statsmodels convention).
    measurement_noise : "estimate" or float
        H, the measurement-noise variance in (unit)²; ``"estimate"`` maximises the likelihood
        over H with the ARMA parameters fixed.
    method : {"auto", "exact", "steady-state"}
        ``"exact"``: statsmodels' filter and smoother over the whole record;
        ``"steady-state"``: exact only over the Riccati transient, then the constant gain
        (DARE + lfilter); ``"auto"``: steady-state from 5000 samples on.
    smooth : bool
        Also compute the smoothed series (NaN otherwise).
    demean : bool
        Remove the sample mean first (the ARMA model has none) and add it back.

    Returns
    -------
    KalmanResult

    Raises
    ------
    DataError
        Bad model, option or measurement noise.
    InsufficientDataError
        Fewer than 10 samples.

    Examples
    --------
    >>> import numpy as np
    >>> from scipy.signal import lfilter
    >>> rng = np.random.default_rng(0)
    >>> drift = lfilter([1.0], [1.0, -0.95], rng.normal(0, 0.1, 3000))
    >>> y = drift + rng.normal(0, 0.5, 3000)
    >>> res = arma_kalman(y, {"ar.L1": 0.95, "sigma2": 0.01}, measurement_noise=0.25)
    >>> bool(np.std(res.filtered - drift) < np.std(y - drift))
    True
    """
    check_choice("method", method, KALMAN_METHODS)
    index = pandas_index(x)
    y_in = to_float_array(x, "x", min_length=MIN_KALMAN_SAMPLES)
    ss = arma_state_space(model)
    mean = float(np.mean(y_in)) if demean else 0.0
    y = y_in - mean
    n = y.size
    notes: list[str] = []

    want_steady = method == "steady-state" or (method == "auto" and n >= STEADY_STATE_MIN_N)
    if isinstance(measurement_noise, str):
        check_choice("measurement_noise", measurement_noise, ("estimate",))
        h, at_lower = _estimate_h(y, ss, use_steady=want_steady)
        source = "estimated"
        if at_lower or h < NEGLIGIBLE_H_RATIO * ss.sigma2:
            notes.append(f"the ML estimate of the measurement noise is negligible (H = {h:.3g}): "
                         "the ARMA model already explains the observations (was it fitted to "
                         "them?), so the filter follows the data; give measurement_noise to "
                         "smooth")
    else:
        h = check_positive("measurement_noise", measurement_noise, allow_zero=True)
        source = "given"

    P, F, Kf = _steady(ss, h)
    run_method = "exact"
    run: _Run
    if want_steady:
        n0 = _riccati_transient(ss, h, P, limit=max(n // 2, 1))
        if n0 is None:
            notes.append("the Riccati recursion did not converge within half the record; "
                         "ran the exact filter")
            run = _exact(y, ss, h, smooth)
        else:
            run = _steady_run(y, ss, h, n0, smooth)
            run_method = "steady-state"
    else:
        run = _exact(y, ss, h, smooth)

    def wrap(arr: FloatArray, name: str) -> Any:
        return pd.Series(arr, index=index, name=name) if index is not None else arr

    return KalmanResult(
        observed=wrap(y_in, "observed"), filtered=wrap(run.filtered + mean, "filtered"),
        smoothed=wrap(run.smoothed + mean, "smoothed"),
        predicted=wrap(run.predicted + mean, "predicted"), innovations=run.innov,
        model=ss.name, ar=tuple(map(float, ss.ar)), ma=tuple(map(float, ss.ma)),
        sigma2=ss.sigma2, measurement_noise=h, measurement_noise_source=source,
        method=run_method, n_transient=run.n0, steady_gain=tuple(map(float, Kf.ravel())),
        innovation_variance=F, loglike=run.loglike, mean=mean, notes=tuple(notes))
