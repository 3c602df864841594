"""Per-term random streams of a simulated gyro axis, generated chunk by chunk.

Each stream yields the *interval-averaged* rate of one noise term in deg/h (every sample is
the average rate over its sample interval, as an integrating gyro reports it), carrying its
state across chunks so that the output does not depend on the chunk size.  Every synthesis
except Kasdin-Walter flicker is exact in discrete time: its expected Allan variance is the
closed form of :meth:`fogts.simulate.noise_spec.NoiseSpec.avar` at every tau = m / fs.

Random streams are split per term with ``numpy.random.Generator.spawn`` (in the fixed order
of :data:`STREAMS`), so adding or removing one term leaves every other term's realisation
unchanged.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence

import numpy as np
import scipy.fft
import scipy.signal

from fogts._typing import FloatArray
from fogts._validate import check_int
from fogts.allan.markov import flicker_poles
from fogts.arma.spec import ArmaSpec
from fogts.choices import FLICKER_METHODS, FlickerMethod
from fogts.errors import FogtsWarning
from fogts.simulate.noise_spec import NoiseSpec

__all__ = ["DEFAULT_CHUNK", "FLICKER_METHODS", "ArmaStream", "FlickerMethod", "axis_streams",
           "flicker_poles", "kasdin_flicker"]


#: Default number of samples generated per chunk.
DEFAULT_CHUNK = 1 << 20
#: One independent random stream per term (fixed order: never reorder, only append).
STREAMS = ("Q", "N", "B", "K", "markov", "sine", "arma")
#: Largest burn-in of an ARMA stream, in samples.
_BURN_IN_CAP = 1_000_000


class TermStream:
    """One noise term of one axis, generated chunk by chunk (state carried across chunks)."""

    def next(self, i0: int, count: int) -> FloatArray:  # pragma: no cover - interface
        """Samples ``i0 .. i0 + count - 1`` of the term, in deg/h."""
        raise NotImplementedError


class WhiteRate(TermStream):
    """White rate noise (angle random walk) with standard deviation ``sd`` per sample."""

    def __init__(self, sd: float, g: np.random.Generator) -> None:
        self.sd, self.g = sd, g

    def next(self, i0: int, count: int) -> FloatArray:
        return self.g.standard_normal(count) * self.sd


class WhiteAngle(TermStream):
    """Rate = (theta_{k+1} - theta_k) fs, theta white with sd ``q`` (deg/h s): quantization."""

    def __init__(self, q: float, fs: float, g: np.random.Generator) -> None:
        self.q, self.fs, self.g = q, fs, g
        self.last = float(g.standard_normal()) * q

    def next(self, i0: int, count: int) -> FloatArray:
        theta = np.empty(count + 1)
        theta[0] = self.last
        theta[1:] = self.g.standard_normal(count) * self.q
        self.last = float(theta[-1])
        return np.diff(theta) * self.fs


class RandomWalk(TermStream):
    """Interval averages of a continuous random walk W with diffusion k^2 (exact):
    y_k = (W_k + W_{k+1}) / 2 + sqrt(k^2 dt / 12) z'_k (the Brownian-bridge mean)."""

    def __init__(self, k: float, fs: float, g: np.random.Generator) -> None:
        dt = 1.0 / fs
        self.step_sd, self.bridge_sd, self.g = k * math.sqrt(dt), k * math.sqrt(dt / 12), g
        self.w = 0.0

    def next(self, i0: int, count: int) -> FloatArray:
        z = self.g.standard_normal(2 * count)
        w = np.empty(count + 1)
        w[0] = self.w
        np.cumsum(z[0::2] * self.step_sd, out=w[1:])
        w[1:] += self.w
        self.w = float(w[-1])
        return 0.5 * (w[:-1] + w[1:]) + z[1::2] * self.bridge_sd


class GaussMarkov(TermStream):
    """Exact discretisation of interval averages of the Gauss-Markov process
    dx = -x/T dt + q dW (one or several, summed).

    With a = exp(-dt/T): x_{k+1} = a x_k + u_k and y_k = (T (1 - a) x_k + v_k) / dt, where
    (u_k, v_k) are jointly Gaussian with var u = q^2 T/2 (1 - a^2),
    var v = q^2 T^3 [h - 2(1 - e^{-h}) + (1 - e^{-2h})/2] (h = dt/T) and
    cov(u, v) = q^2 T^2 (1 - a)^2 / 2; x_0 is drawn from the stationary N(0, q^2 T / 2).

    Writing u = l11 z1 and v = l21 z1 + l22 z2 (Cholesky), each pole's output is one IIR
    filter of z1, y = [c1 + (g l11 - a c1) z^-1] / (1 - a z^-1) z1 with c1 = l21/dt and
    g = T(1 - a)/dt, plus the white part (l22/dt) z2.  The white parts of all poles are
    independent, so their sum is drawn as one white sequence of variance sum (l22/dt)^2:
    P + 1 normal draws per sample for P poles.
    """

    def __init__(self, q: Sequence[float] | FloatArray, T: Sequence[float] | FloatArray,
                 fs: float, g: np.random.Generator) -> None:
        dt = 1.0 / fs
        q_arr, t_arr = np.asarray(q, dtype=np.float64), np.asarray(T, dtype=np.float64)
        h = dt / t_arr
        one_minus_a = -np.expm1(-h)
        a = 1.0 - one_minus_a
        one_minus_a2 = -np.expm1(-2 * h)
        var_u = q_arr**2 * t_arr / 2 * one_minus_a2
        f = np.where(h < 1e-2, h**3 / 3 - h**4 / 4 + 7 * h**5 / 60 - h**6 / 24,
                     h - 2 * one_minus_a + one_minus_a2 / 2)
        var_v = q_arr**2 * t_arr**3 * f
        cov = q_arr**2 * t_arr**2 * one_minus_a**2 / 2
        l11 = np.sqrt(var_u)
        l21 = np.divide(cov, l11, out=np.zeros_like(cov), where=l11 > 0)
        l22 = np.sqrt(np.maximum(var_v - l21**2, 0.0))
        gain = t_arr * one_minus_a / dt
        c1 = l21 / dt
        self.a = a
        self.b = np.stack([c1, gain * l11 - a * c1], axis=1)
        self.white_sd = float(np.sqrt(np.sum((l22 / dt) ** 2)))
        # one stream per pole (+ one for the white parts), so that the output does not
        # depend on the chunk size
        gens = g.spawn(q_arr.size + 1)
        self.gens, self.white_gen = gens[:-1], gens[-1]
        x0 = np.array([gj.standard_normal() for gj in self.gens]) * q_arr * np.sqrt(t_arr / 2)
        self.zi = gain * x0  # lfilter state: y_0 = c1 z1_0 + gain x_0

    def next(self, i0: int, count: int) -> FloatArray:
        out = self.white_gen.standard_normal(count) * self.white_sd
        for j in range(self.a.size):
            z1 = self.gens[j].standard_normal(count)
            y, zf = scipy.signal.lfilter(self.b[j], [1.0, -self.a[j]], z1,
                                         zi=self.zi[j:j + 1])
            self.zi[j] = zf[0]
            out += y
        return out


class Sine(TermStream):
    """Interval averages of Omega sin(2 pi f t + phi): Omega sinc(f dt) sin(2 pi f (t + dt/2) + phi)."""

    def __init__(self, amp: float, f0: float, fs: float, g: np.random.Generator) -> None:
        self.amp = amp * float(np.sinc(f0 / fs))
        self.w, self.fs = 2 * math.pi * f0, fs
        self.phase = float(g.uniform(0.0, 2 * math.pi))

    def next(self, i0: int, count: int) -> FloatArray:
        t = (np.arange(i0, i0 + count, dtype=np.float64) + 0.5) / self.fs
        return self.amp * np.sin(self.w * t + self.phase)


class Precomputed(TermStream):
    """A term generated whole beforehand, served in chunks."""

    def __init__(self, values: FloatArray) -> None:
        self.values = values

    def next(self, i0: int, count: int) -> FloatArray:
        return self.values[i0:i0 + count]


class ArmaStream(TermStream):
    """An ARMA series, ``scipy.signal.lfilter([1, theta...], [1, -phi...], a)`` with the
    filter state carried across chunks and through a burn-in (Box, Jenkins & Reinsel,
    *Time Series Analysis*, ch. 3).

    ``burn_in=None`` discards :meth:`fogts.arma.spec.ArmaSpec.burn_in` samples (at most
    10^6, with a warning when that cap is reached).
    """

    def __init__(self, spec: ArmaSpec, rng: np.random.Generator, burn_in: int | None) -> None:
        self.spec = spec
        self.rng = rng
        self.b = np.r_[1.0, np.asarray(spec.ma, dtype=np.float64)]
        self.a = np.r_[1.0, -np.asarray(spec.ar, dtype=np.float64)]
        self.sd = math.sqrt(spec.sigma2)
        self.zi = np.zeros(max(len(self.a), len(self.b)) - 1)
        burn = spec.burn_in() if burn_in is None else check_int("burn_in", burn_in, minimum=0)
        if burn_in is None and burn >= _BURN_IN_CAP and spec.ar_radius > 0:
            warnings.warn(f"AR pole modulus {spec.ar_radius:.8g} is close to 1: the burn-in is "
                          f"capped at {burn} samples, so the start may not be stationary",
                          FogtsWarning, stacklevel=3)
        self.burn_in = burn
        done = 0
        while done < burn:
            c = min(DEFAULT_CHUNK, burn - done)
            self.next(done, c)
            done += c

    def next(self, i0: int, count: int) -> FloatArray:
        e = self.rng.standard_normal(count) * self.sd
        if self.zi.size == 0:
            return e + self.spec.const
        y, self.zi = scipy.signal.lfilter(self.b, self.a, e, zi=self.zi)
        return np.asarray(y, dtype=np.float64) + self.spec.const


def kasdin_flicker(n: int, b: float, g: np.random.Generator) -> FloatArray:
    """Kasdin-Walter 1/f (alpha = 1) noise of ``n`` samples, two-sided PSD ~ b^2/(2 pi f).

    h_0 = 1, h_k = h_{k-1} (k - 1 + alpha/2) / k (Kasdin, "Discrete simulation of colored
    noise and stochastic processes and 1/f^alpha power law noise generation", Proc. IEEE
    83(5), 1995, eq. 116) convolved with white noise of variance b^2 by a zero-padded FFT
    (linear, not circular, convolution), in O(n log n) and with the whole record in memory.
    The samples are sampled rather than interval-averaged flicker: the integral of the
    discrete spectrum puts the Allan deviation 20 %, 7.4 %, 2.5 % and 0.8 % above
    :data:`~fogts.allan.terms.B_PLATEAU` b at m = 1, 2, 4 and 8 samples.
    """
    k = np.arange(1, n, dtype=np.float64)
    h = np.empty(n)
    h[0] = 1.0
    h[1:] = np.cumprod((k - 0.5) / k)
    w = g.standard_normal(n) * b
    size = scipy.fft.next_fast_len(2 * n, real=True)
    y = scipy.fft.irfft(scipy.fft.rfft(w, size) * scipy.fft.rfft(h, size), size)[:n]
    return np.ascontiguousarray(y, dtype=np.float64)


def axis_streams(spec: NoiseSpec, arma: ArmaSpec | None, *, fs: float, n: int,
                 duration: float, flicker: str, rng: np.random.Generator) -> list[TermStream]:
    """The streams of one axis, in the order of :data:`STREAMS`, each on its own generator.

    Flicker (B) is the Markov sum of :func:`flicker_poles` (``flicker="markov"``) or
    :func:`kasdin_flicker` generated whole (``"kasdin"``).
    """
    gens = dict(zip(STREAMS, rng.spawn(len(STREAMS)), strict=True))
    streams: list[TermStream] = []
    if spec.Q > 0:
        streams.append(WhiteAngle(spec.internal("Q"), fs, gens["Q"]))
    if spec.N > 0:
        streams.append(WhiteRate(spec.internal("N") * math.sqrt(fs), gens["N"]))
    if spec.B > 0:
        if flicker == "kasdin":
            streams.append(Precomputed(kasdin_flicker(n, spec.B, gens["B"])))
        else:
            T, q = flicker_poles(fs, duration)
            streams.append(GaussMarkov(q * spec.B, T, fs, gens["B"]))
    if spec.K > 0:
        streams.append(RandomWalk(spec.internal("K"), fs, gens["K"]))
    if spec.q_c > 0:
        streams.append(GaussMarkov([spec.q_c], [spec.T_c], fs, gens["markov"]))
    if spec.Omega_0 > 0:
        streams.append(Sine(spec.Omega_0, spec.f_0, fs, gens["sine"]))
    if arma is not None:
        streams.append(ArmaStream(arma, gens["arma"], None))
    return streams
