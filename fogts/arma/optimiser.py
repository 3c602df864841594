"""Maximise the exact ARMA likelihood: damped Newton steps from one or more starts.

The profile objective f = n/2 log(S/n) + D/2 of :mod:`fogts.arma.likelihood` is minimised by
damped Newton steps with a backtracking (Armijo) line search inside the stationarity and
invertibility region.  The Hessian is the analytic one of S (cheap; on long series with
D's from the start-up block), replaced by the Fisher information when it is not positive
definite, or the finite-difference Hessian of the exact gradient (``exact=True``, used to
polish fits on short series, where it matters on the flat ridges of non-identified
models).

A nearly cancelling AR/MA root pair (a near-redundant model, e.g. ARMA(1,1) on nearly white
data) makes the likelihood flat along the cancellation ridge, with possibly several maxima on
it: :func:`maximise` then also tries the mirrored pair and statsmodels' own start values and
keeps the highest likelihood.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from fogts._typing import FloatArray
from fogts.arma.likelihood import Evaluation, ExactLikelihood
from fogts.arma.region import UNIT_ROOT_GAP, admissible, shrink_into_region, unit_root_gap
from fogts.arma.startup_curvature import d_hessian

__all__ = ["PREFIXES", "PRESAMPLE", "NewtonResult", "maximise", "newton", "solve", "warm_start"]

_MAX_ITER = 100
PRESAMPLE = 100_000      # long series: Newton first runs on this many leading samples
PREFIXES = (1 << 21, 1 << 24)  # ... and on very long ones then on these many
_SAME_START = 1e-3       # warm starts this close lead to the same whole-series optimum
_LONG_MAX_TRIALS = 4     # line-search evaluations with D's curvature beyond 4 x PREFIXES[0]
_SMALL_STEP = 1e-6        # a Newton step this small is the last one


@dataclass
class NewtonResult:
    """Where Newton's method stopped, and the derivatives it used there."""

    ev: Evaluation
    converged: bool
    n_iter: int
    msgs: list[str]
    dS: FloatArray | None = None      # gradient of S and D at the last Newton iterate
    dD: FloatArray | None = None
    HS: FloatArray | None = None      # Hessian of S and D used at the last Newton iterate
    HD: FloatArray | None = None
    at_unit_root: bool = False        # stopped at an inverse AR root within UNIT_ROOT_GAP of 1


#: With ``d_curvature``, this many steps in a row accepted only after this much damping
#: (five halvings) end the run unconverged (:func:`solve` then iterates without D's
#: curvature); a single damped step near a unit root is normal.
_HD_GIVE_UP_STEP = 1.0 / 32
_HD_GIVE_UP_RUN = 3


# Over 80 lines: one damped-Newton loop whose stopping rules (convergence, failed line
# search, damping with D's curvature, unit root) share its state; the passes are the model's.
def newton(model: ExactLikelihood, phi: FloatArray, theta: FloatArray, *,
           small_step: float = _SMALL_STEP, exact: bool = False,
           max_iter: int | None = None, d_curvature: bool = False,
           max_trials: int | None = None) -> NewtonResult:
    """Minimise the profile objective f from (phi, theta) by damped Newton steps.

    ``exact=False`` uses the analytic Hessian of S (cheap: 2 lfilter passes), with
    ``d_curvature`` plus the Hessian of D from the start-up block alone
    (:func:`fogts.arma.startup_curvature.d_hessian`: no pass over the data; without it
    Newton crawls along the boundary when the optimum is near a unit root, 114 iterations
    instead of 17 on a 4e6-sample white + random-walk record); ``exact=True`` the
    finite-difference Hessian of the exact gradient (4(p+q) gradients; used on short
    series, where it matters on flat ridges of non-identified models).  The line search
    halves a step down to 1e-12 of it, evaluating at most ``max_trials`` admissible
    candidates (if given); finding no descent ends the run.
    """
    max_iter = _MAX_ITER if max_iter is None else max_iter
    n, p, q = model.nu, model.p, model.q
    k = p + q
    msgs: list[str] = []
    ev = model.evaluate(phi, theta)
    converged = False
    n_iter = 0
    dS = dD = HS = HD = None
    damped = 0  # damped steps in a row
    for n_iter in range(1, max_iter + 1):
        if exact:
            dS, dD, _ = model.derivatives(ev, hessian=False)
            HS, HD = model.fd_hessians(ev)
        else:
            dS, dD, HS = model.derivatives(ev, hessian=True)
            HD = d_hessian(model, ev) if d_curvature else np.zeros((k, k))
        assert HS is not None
        grad = 0.5 * n / ev.S * dS + 0.5 * dD
        Hf = model.hessian_f(ev, dS, HS) + 0.5 * HD
        try:
            np.linalg.cholesky(Hf)
        except np.linalg.LinAlgError:
            Hf = n * model.information(ev.phi, ev.theta)
            Hf += 1e-8 * np.trace(Hf) / k * np.eye(k)
        try:
            step = np.linalg.solve(Hf, grad)
        except np.linalg.LinAlgError:
            step = np.linalg.lstsq(Hf, grad, rcond=None)[0]
        beta = ev.beta
        if float(np.max(np.abs(step))) < small_step:
            cand = beta - step
            if admissible(cand[:p], cand[p:]):
                ev2 = model.evaluate(cand[:p], cand[p:])
                if ev2.f <= ev.f + 1e-6:
                    ev = ev2
            converged = True
            break
        accepted, t = _line_search(model, ev, step, float(grad @ step), max_trials)
        if accepted is None:
            # no descent possible: at the optimum up to rounding, or stuck on the boundary
            dec = float(grad @ step)
            converged = dec < 1e-6
            if not converged:
                msgs.append(f"line search failed at iteration {n_iter} "
                            f"(Newton decrement {dec:.3g}); the optimum may lie on the "
                            "stationarity/invertibility boundary")
            break
        ev = accepted
        damped = damped + 1 if t < _HD_GIVE_UP_STEP else 0
        if d_curvature and damped >= _HD_GIVE_UP_RUN:
            # D's start-up-block curvature misleads here (seen along a near-cancelling AR/MA
            # pair: 100 iterations of ~30 halvings each on 1e6 white-noise block means);
            # the caller starts again without it
            msgs.append(f"steps damped below {_HD_GIVE_UP_STEP:g} at iterations "
                        f"{n_iter - damped + 1}-{n_iter} with D's curvature")
            break
        if model.mean and unit_root_gap(ev.phi) < UNIT_ROOT_GAP:
            # the restricted likelihood runs to the unit root, outside the region
            msgs.append(f"stopped at iteration {n_iter}: an inverse AR root within "
                        f"{UNIT_ROOT_GAP:g} of 1")
            return NewtonResult(ev=ev, converged=False, n_iter=n_iter, msgs=msgs, dS=dS,
                                dD=dD, HS=HS, HD=HD, at_unit_root=True)
    else:
        msgs.append(f"Newton's method did not converge in {max_iter} iterations")
    return NewtonResult(ev=ev, converged=converged, n_iter=n_iter, msgs=msgs, dS=dS, dD=dD,
                        HS=HS, HD=HD)


def _line_search(model: ExactLikelihood, ev: Evaluation, step: FloatArray, slope: float,
                 max_trials: int | None) -> tuple[Evaluation | None, float]:
    """Backtracking (Armijo) along -step from ``ev`` (``slope``: grad . step) inside the
    region: the accepted evaluation and its step fraction (None if none within 1e-12 of
    the step or ``max_trials`` admissible candidates)."""
    p = model.p
    beta = ev.beta
    t, trials = 1.0, 0
    while t > 1e-12 and (max_trials is None or trials < max_trials):
        cand = beta - t * step
        if admissible(cand[:p], cand[p:]):
            trials += 1
            ev2 = model.evaluate(cand[:p], cand[p:])
            if ev2.f <= ev.f - 1e-4 * t * slope:
                return ev2, t
        t *= 0.5
    return None, t


def _stage(judge: ExactLikelihood | None, pre: NewtonResult, phi: FloatArray,
           theta: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The next start after a shorter series' Newton run ``pre`` from (phi, theta): its
    optimum; one within 1e-3 of the region's boundary (a unit AR root) only if ``judge``'s
    likelihood is higher there than at (phi, theta) (without a judge, if admissible)."""
    if admissible(pre.ev.phi, pre.ev.theta, margin=1e-3):
        return pre.ev.phi, pre.ev.theta
    if admissible(pre.ev.phi, pre.ev.theta, margin=0.0) and (
            judge is None
            or judge.evaluate(pre.ev.phi, pre.ev.theta).f < judge.evaluate(phi, theta).f):
        return pre.ev.phi, pre.ev.theta
    return phi, theta


Path = list[tuple[FloatArray, FloatArray]]


def warm_start(xs: FloatArray, model: ExactLikelihood, phi: FloatArray, theta: FloatArray,
               known: Sequence[Path] = ()) -> Path | None:
    """The starts of the whole series' Newton iterations from (phi, theta) on long series:
    (phi, theta) and where each stage ended (the last is the start).

    Above 4 x ``PRESAMPLE`` samples Newton first runs on the first ``PRESAMPLE`` samples
    (``xs``), then, for each size m of ``PREFIXES`` with more than 4 m samples, on the first
    m samples of the model's series from there: each stage's optimum is within a few of its
    standard errors of the next one's, so the whole series needs only the last few
    iterations (cheap ones on the shorter series).  A stage's optimum near the region's
    boundary is taken if the next series' likelihood is higher there than at the stage's
    start; the last prefix's (within a few standard errors of the whole series') if it is
    admissible: whole-series evaluations are what the stages save.  None if a stage ends
    where that stage of a ``known`` path did (the rest would repeat it).
    """
    n, p, q = model.n, model.p, model.q
    prefixes = [ExactLikelihood(model.x[:m], p, q, mean=model.mean, scale=model.scale,
                                offsets=model.offsets, work=model.work.prefix(m))
                for m in PREFIXES if n > 4 * m]
    path: Path = [(phi, theta)]
    if n > 4 * PRESAMPLE:
        pre = newton(ExactLikelihood(xs[:PRESAMPLE], p, q, mean=model.mean), phi, theta,
                     small_step=1e-4, d_curvature=True)
        path.append(_stage(prefixes[0] if prefixes else model, pre, *path[-1]))
    for i, prefix in enumerate(prefixes):
        # the same stage of a known path: its entry len(path) - 1
        if any(len(other) >= len(path) and _same_start(path[-1], other[len(path) - 1])
               for other in known):
            return None
        pre = newton(prefix, *path[-1], small_step=1e-5, d_curvature=True)
        judge = prefixes[i + 1] if i + 1 < len(prefixes) else None
        path.append(_stage(judge, pre, *path[-1]))
    if any(_same_start(path[-1], other[-1]) for other in known):
        return None
    return path


def solve(model: ExactLikelihood, phi: FloatArray, theta: FloatArray, *,
          polish: bool) -> NewtonResult:
    """Newton on the whole series from (phi, theta) (on long series the end of
    :func:`warm_start`), exact polish if ``polish``.

    ``polish`` continues with the finite-difference Hessian of the exact gradient (short
    series).
    """
    n = model.n
    # on long series (those with a presample stage) D's curvature is in the Newton Hessian;
    # shorter ones keep the iterations they had (their fits, and the golden outputs of a
    # 1.08e5-sample record, unchanged)
    long = n > 4 * PRESAMPLE
    # after the last prefix stage (2^24 samples) the start is within a few standard errors
    # of the optimum, and plain Newton steps reach it: with D's curvature, on 1e8 samples of
    # white + random walk, ARMA(2,1) ran four whole-series iterations into a failed line
    # search before the plain run (19 s wasted); on a stationary ARMA(2,1) both take the
    # same steps
    curvature = long and n <= 4 * PREFIXES[-1]
    # a whole-series evaluation is costly: with D's curvature a step that finds no descent
    # in four evaluations (damped to 1/8) ends the run, which then starts again without it
    res = newton(model, phi, theta, d_curvature=curvature,
                 max_trials=_LONG_MAX_TRIALS if curvature and n > 4 * PREFIXES[0] else None)
    curved = curvature
    if long and not res.converged and not res.at_unit_root:
        # the steps went astray (D's curvature misled them, a run of damped ones; or the
        # plain steps crawled along the boundary): again the other way; a run stopped at a
        # unit root stopped where the likelihood leads
        other = newton(model, phi, theta, d_curvature=not curvature,
                       max_trials=_LONG_MAX_TRIALS if not curvature else None)
        if other.converged or other.ev.f < res.ev.f:
            res, curved = other, not curvature
    if long and not curved:
        # the standard errors of a long series take D's curvature with S's (as the exact
        # Hessians of a short one do): at the optimum a plain run reached, from the start-up
        # block alone
        res.HD = d_hessian(model, res.ev)
    if polish:
        # polish with the exact Hessian; it also gives the observed information
        res2 = newton(model, res.ev.phi, res.ev.theta, small_step=1e-7, exact=True,
                      max_iter=20)
        if res2.ev.f <= res.ev.f:
            return NewtonResult(ev=res2.ev, converged=res2.converged,
                                n_iter=res.n_iter + res2.n_iter,
                                msgs=res2.msgs if res2.converged else res.msgs + res2.msgs,
                                dS=res2.dS, dD=res2.dD, HS=res2.HS, HD=res2.HD)
        res.n_iter += res2.n_iter
    return res


def cancelling_pair(phi: FloatArray, theta: FloatArray, tol: float = 0.15
                    ) -> tuple[FloatArray, FloatArray, tuple[complex, complex]] | None:
    """Inverse AR and MA roots without their closest real pair, and the pair, if it cancels.

    A near-common factor of phi(B) and theta(B) makes the model nearly redundant: the
    likelihood is flat along the cancellation ridge and can have several local maxima on it.
    """
    if phi.size == 0 or theta.size == 0:
        return None
    ar_roots = np.roots(np.r_[1.0, -phi])        # inverse AR roots
    ma_roots = np.roots(np.r_[1.0, theta])       # inverse MA roots
    gap = np.abs(ar_roots[:, None] - ma_roots[None, :])
    i, j = np.unravel_index(int(np.argmin(gap)), gap.shape)
    if gap[i, j] > tol or abs(ar_roots[i].imag) > 1e-8 or abs(ma_roots[j].imag) > 1e-8:
        return None
    return np.delete(ar_roots, i), np.delete(ma_roots, j), (ar_roots[i], ma_roots[j])


def second_starts(xs: FloatArray, p: int, q: int, base_ar: FloatArray, base_ma: FloatArray,
                  pair: tuple[complex, complex], mean: bool = False
                  ) -> list[tuple[FloatArray, FloatArray]]:
    """Further starts for a nearly redundant fit: the mirrored pair and statsmodels' start.

    The mirrored pair negates both nearly cancelling roots (the other side of the ridge);
    statsmodels' ``start_params`` (on at most ``PRESAMPLE`` samples, demeaned if ``mean``)
    is the start of its own optimiser, so its basin is explored too.
    """
    from statsmodels.tsa.arima.model import ARIMA

    starts = []
    r, m = pair
    phi = -np.real(np.poly(np.r_[base_ar, -r]))[1:]
    theta = np.real(np.poly(np.r_[base_ma, -m]))[1:]
    starts.append((phi, theta))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            y = xs[:PRESAMPLE] - (float(np.mean(xs[:PRESAMPLE])) if mean else 0.0)
            sp = np.asarray(ARIMA(y, order=(p, 0, q), trend="n").start_params)
            starts.append((sp[:p].copy(), sp[p:p + q].copy()))
        except (ValueError, np.linalg.LinAlgError):
            pass
    out = []
    for phi, theta in starts:
        if np.all(np.isfinite(phi)) and np.all(np.isfinite(theta)):
            if not admissible(phi, theta, margin=1e-3):
                phi, theta = shrink_into_region(phi, theta)
            out.append((phi, theta))
    return out


def _same_start(a: tuple[FloatArray, FloatArray], b: tuple[FloatArray, FloatArray]) -> bool:
    """Whether two starts (phi, theta) agree to 1e-3 in every coefficient."""
    return bool(np.max(np.abs(np.r_[a[0] - b[0], a[1] - b[1]]), initial=0.0) < _SAME_START)


def maximise(xs: FloatArray, model: ExactLikelihood, phi: FloatArray, theta: FloatArray, *,
             polish: bool) -> tuple[NewtonResult, int]:
    """The maximum likelihood from (phi, theta), and from further starts if the fit is redundant.

    Returns the best :class:`NewtonResult` and the Newton iterations of all starts together.
    """
    long = model.n > 4 * PRESAMPLE
    first = warm_start(xs, model, phi, theta)
    assert first is not None
    seen = [first]
    res = solve(model, *first[-1], polish=polish)
    n_iter = res.n_iter
    if model.mean and unit_root_gap(res.ev.phi) < UNIT_ROOT_GAP:
        return res, n_iter        # at a unit root: no mean to estimate, nothing to compare
    found = cancelling_pair(res.ev.phi, res.ev.theta)
    if found is not None:
        for start in second_starts(xs, model.p, model.q, *found, mean=model.mean):
            # a start whose warm-up reaches where an earlier one's did would repeat its
            # whole-series iterations
            path = warm_start(xs, model, *start, known=seen if long else ())
            if path is None:
                continue
            seen.append(path)
            res_alt = solve(model, *path[-1], polish=polish)
            n_iter += res_alt.n_iter
            if res_alt.ev.f < res.ev.f - 1e-9:
                res = res_alt
    return res, n_iter
