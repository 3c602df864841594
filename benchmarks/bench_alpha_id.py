"""Noise identification and confidence intervals against allantools' noise-ID pipeline.

Speed: one ``fogts.allan.confidence.confidence_table`` call (lag-1 ACF noise ID, Greenhall
EDF and chi-squared interval at every octave tau) against what a user does with allantools:
``allantools.autocorr_noise_id`` (phase data, alpha clipped to [-2, 2]), ``edf_greenhall``
and ``confidence_interval`` per tau (``confidence_interval_noiseID`` does the same but
asserts on alpha < -2).  allantools only identifies taus with at least 30 decimated points, so both sides
get those taus only.  Ratio = allantools seconds / fogts seconds (higher is better).

Accuracy: the share of correctly identified power-law types (white/flicker PM, white/flicker
FM, random-walk FM; fixed seeds) at a given number of averaged points, fogts vs
``allantools.autocorr_noise_id`` on the same series.  These Monte-Carlo studies are too slow
for the test suite, which checks fixed seeds only.

Run: ``python -m benchmarks.bench_alpha_id [--quick]``.
"""

from __future__ import annotations

import numpy as np

from benchmarks.cli import script_main
from benchmarks.metric import Metric, accuracy_metric
from benchmarks.timing import measure, speed_from

ALPHAS = (2, 1, 0, -1, -2)


def _kasdin(n: int, beta: float, rng: np.random.Generator) -> np.ndarray:
    """1/f**beta noise, Kasdin & Walter (1992) filter h_k = h_{k-1} (beta/2 + k - 1) / k."""
    k = np.arange(1, n)
    h = np.concatenate(([1.0], np.cumprod((beta / 2.0 + k - 1.0) / k)))
    size = 2 * n
    w = rng.standard_normal(n)
    return np.fft.irfft(np.fft.rfft(w, size) * np.fft.rfft(h, size), size)[:n]


def _noise(alpha: int, n: int, rng: np.random.Generator) -> np.ndarray:
    """Rate ("frequency") series with S_y(f) ~ f**alpha."""
    if alpha == 2:
        return np.diff(rng.standard_normal(n + 1))
    if alpha == 1:
        return np.diff(_kasdin(n + 1, 1.0, rng))
    if alpha == 0:
        return rng.standard_normal(n)
    if alpha == -1:
        return _kasdin(n, 1.0, rng)
    return np.cumsum(rng.standard_normal(n))


def _speed(quick: bool) -> list[Metric]:
    import allantools

    from fogts.allan.confidence import confidence_table

    n = 20_000 if quick else 200_000
    y = _noise(0, n, np.random.default_rng(1)) + 0.3 * _noise(-2, n, np.random.default_rng(2))
    x = np.concatenate(([0.0], np.cumsum(y)))
    m = 2 ** np.arange(0, 30)
    m = m[n // m + 1 >= 30]
    dev = allantools.oadev(y, rate=1.0, data_type="freq", taus=m)[1]

    def ours() -> object:
        return confidence_table(y, fs_hz=1.0, kind="oadev", m=m, dev=dev)

    def peer() -> list[tuple[float, float]]:
        out = []
        for af, d in zip(m.tolist(), dev.tolist(), strict=True):
            alpha = int(np.clip(allantools.autocorr_noise_id(x, af, data_type="phase",
                                                             dmax=2)[0], -2, 2))
            edf = allantools.edf_greenhall(alpha=alpha, d=2, m=af, N=x.size,
                                           overlapping=True, modified=False)
            out.append(allantools.confidence_interval(d, edf, ci=0.683))
        return out

    ref = np.array(peer())
    got = ours()
    rel = float(np.max(np.abs(np.column_stack([got.ci_low, got.ci_high]) / ref - 1.0)))  # type: ignore[attr-defined]
    timing = measure({"fogts": ours, "peer": peer}, repeat=3, min_total_s=1.0 if quick else 3.0)
    tag = f"n={n:.0e}".replace("+0", "")
    return [
        speed_from(timing, f"speed.confidence.{tag}", f"noise ID + EDF + CI, {m.size} octave "
                   f"taus, {n} samples", peer="allantools noiseID",
                   details={"taus": int(m.size)}),
        accuracy_metric(f"accuracy.confidence_vs_allantools.{tag}",
                        "largest relative CI difference to allantools' noise-ID pipeline "
                        "(differs where the two identify different alphas)", value=rel,
                        better="lower", abs_tolerance=1e-3),
    ]


def _accuracy(quick: bool) -> list[Metric]:
    import allantools

    from fogts.allan.noise_identification import identify_noise

    seeds = 10 if quick else 40
    out: list[Metric] = []
    for points in (32, 256) if quick else (32, 256, 4096):
        m = 16
        n = points * m
        ours = peer = total = 0
        per_type: dict[str, list[float]] = {}
        for alpha in ALPHAS:
            hit_o = hit_p = 0
            for seed in range(seeds):
                y = _noise(alpha, n, np.random.default_rng(1000 * (alpha + 3) + seed))
                a_o = int(identify_noise(y, [m], fs_hz=1.0, kind="oadev")[0])
                a_p = int(np.clip(allantools.autocorr_noise_id(y, m, data_type="freq",
                                                               dmax=1)[0], -2, 2))
                hit_o += a_o == alpha
                hit_p += a_p == alpha
            per_type[str(alpha)] = [hit_o / seeds, hit_p / seeds]
            ours += hit_o
            peer += hit_p
            total += seeds
        out.append(accuracy_metric(
            f"accuracy.alpha_id.points={points}",
            f"noise types identified correctly, {points} averaged points (m = {m}), "
            f"{seeds} seeds x 5 types; allantools: {peer / total:.2f}",
            value=ours / total, better="higher", abs_tolerance=0.05,
            details={"allantools": peer / total, "per_alpha_fogts_allantools": per_type}))
    return out


def metrics(quick: bool) -> list[Metric]:
    """Measure and return the figures (the runner's entry point)."""
    return _speed(quick) + _accuracy(quick)


def main(argv: list[str] | None = None) -> int:
    return script_main(__doc__, metrics, argv, quick_help="smaller problems, fewer seeds")


if __name__ == "__main__":
    raise SystemExit(main())
