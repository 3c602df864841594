"""Gyro grades: the ranges of angle random walk N and bias instability B real gyros span.

N in deg/sqrt(h), B in deg/h (Allan-variance bias instability, the flicker floor /
:data:`~fogts.allan.terms.B_PLATEAU`; IEEE Std 952-1997 Annex C).  Each range is the span of the
published figures quoted beside it, widened by a factor of about 2 to 5 on each side,
because datasheet figures are specification limits (a unit is often better than its limit)
and in-run B from an Allan curve is usually below a datasheet's turn-on or repeatability
bias.  A pair (N, B) is plausible if one grade holds both (:func:`grades_of`;
:func:`fogts.allan.plausibility.check_plausibility`).

=============  ======================  ===============  ==============  ==========================
grade          technology              N (deg/sqrt(h))  B (deg/h)       anchors
=============  ======================  ===============  ==============  ==========================
strategic      FOG, RLG (marine,       3e-5 .. 1e-3     1e-4 .. 3e-3    best instruments reach
               submarine, space)                                        N, B of order 1e-4 (order
                                                                        of magnitude only: few
                                                                        datasheets are public) [2]_;
                                                                        "inertial grade" N < 1e-3,
                                                                        B < 0.01 [1]_
navigation     RLG, FOG (1 nmi/h       3e-4 .. 1e-2     1e-3 .. 5e-2    Honeywell HG9900: N <= 0.002,
               aircraft/marine INS)                                     B <= 0.003; GG1320AN:
                                                                        N <= 0.0035, B <= 0.0035
                                                                        [3]_; aviation-grade bias
                                                                        ~0.001..0.01 [6]_
tactical       FOG, RLG, high-end      1e-3 .. 0.5      3e-3 .. 30      KVH/Emcore DSP-1750:
               MEMS                                                     N <= 0.012, B <= 0.1 [5]_;
                                                                        Honeywell HG1700: N 0.125..
                                                                        0.3, B 1..10 [3]_; tactical
                                                                        grade N 0.05..0.5, B 0.1..10
                                                                        [1]_ [2]_
industrial     industrial/automotive   0.05 .. 10       0.5 .. 100      ADIS16488: N 0.26, B 5.1;
               MEMS                                                     ADIS16448: 0.66, 14.5;
                                                                        ADIS16405: 2.0, 25 (0.007
                                                                        deg/s); ADXRS150/300 rate
                                                                        noise 0.05/0.1 deg/s/
                                                                        sqrt(Hz), N 3/6 [4]_
consumer       consumer MEMS           0.07 .. 6        3 .. 1000       MPU-6050 0.005, BMI160 0.007,
                                                                        L3G4200D 0.03 deg/s/sqrt(Hz):
                                                                        N 0.3, 0.4, 1.8 (N = 60 x
                                                                        noise density) [4]_; "rate
                                                                        grade" N > 0.5, B 10..1000
                                                                        [1]_ [2]_
=============  ======================  ===============  ==============  ==========================

The envelope, the union of the grades, is N in [3e-5, 10] deg/sqrt(h) and B in [1e-4, 1e3]
deg/h.  Its lower end lies a factor of about 3 below the best strategic-grade FOG and RLG
(~1e-4 in both); its upper end is a factor of ~1.5 to 3 above the noisiest rate gyros we
know datasheets of (ADXRS300, 0.1 deg/s/sqrt(Hz), N = 6) and the top of the "rate grade"
bias range (1000 deg/h).  Out of scope, and so reported as implausible: electrostatically
suspended gyros (not rate sensors), metre-scale ring lasers for geodesy, atom-interferometer
gyros.

References
----------
.. [1] N. Yazdi, F. Ayazi and K. Najafi, "Micromachined inertial sensors", Proc. IEEE
   86(8):1640-1659, 1998, Table I (rate, tactical and inertial grade).
.. [2] V. M. N. Passaro, A. Cuccovillo, L. Vaiani, M. De Carlo and C. E. Campanella,
   "Gyroscope technology and applications: a review in the industrial perspective",
   Sensors 17(10):2284, 2017 (grade classification and technology survey).
.. [3] Honeywell Aerospace datasheets: HG9900 and HG1700 IMUs, GG1320AN digital laser gyro.
.. [4] Analog Devices datasheets: ADIS16405, ADIS16448, ADIS16488 IMUs; ADXRS150, ADXRS300
   gyros.  InvenSense MPU-6050, Bosch BMI160 and STMicroelectronics L3G4200D datasheets
   (rate noise density).
.. [5] KVH (now Emcore) DSP-1750 fiber optic gyro datasheet (ARW <= 0.012 deg/sqrt(h),
   i.e. 0.7 deg/h/sqrt(Hz); bias instability <= 0.1 deg/h, typ. 0.05 deg/h).
.. [6] P. D. Groves, *Principles of GNSS, Inertial, and Multisensor Integrated Navigation
   Systems*, 2nd ed., Artech House, 2013, ch. 4 (grades of IMU, gyro biases and noise).
.. [7] IEEE Std 952-1997, Annex C (definitions of N and B; see DESIGN.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import pandas as pd

__all__ = ["B_ENVELOPE", "GRADE_BY_KEY", "GYRO_GRADES", "N_ENVELOPE", "Bounds", "GyroGrade",
           "grade_table", "grades_of"]

#: An inclusive range ``(low, high)``.
Bounds = tuple[float, float]


@dataclass(frozen=True)
class GyroGrade:
    """One grade of gyro: the N and B ranges its instruments span.

    Attributes
    ----------
    key : str
        Short name (``"strategic"``, ``"navigation"``, ``"tactical"``, ``"industrial"``,
        ``"consumer"``).
    label : str
        Noun phrase for messages ("tactical-grade gyro").
    technology : str
    n_range : Bounds
        Angle random walk N, deg/sqrt(h).
    b_range : Bounds
        Bias instability B, deg/h.
    anchors : str
        The published figures the ranges were widened from (see the module docstring).
    """

    key: str
    label: str
    technology: str
    n_range: Bounds
    b_range: Bounds
    anchors: str

    def contains(self, N: float | None, B: float | None) -> bool:
        """True if every available value lies in this grade's range."""
        return ((N is None or self.n_range[0] <= N <= self.n_range[1])
                and (B is None or self.b_range[0] <= B <= self.b_range[1]))

    def distance(self, N: float | None, B: float | None) -> float:
        """RMS over the available values of the log-distance to the middle of the range,
        in units of the half-width (0 at the middle, 1 on the edge)."""
        offsets = [_offset(v, r) for v, r in ((N, self.n_range), (B, self.b_range))
                   if v is not None]
        if not offsets:
            return math.nan
        return math.sqrt(sum(u * u for u in offsets) / len(offsets))


def _offset(value: float, bounds: Bounds) -> float:
    lo, hi = math.log10(bounds[0]), math.log10(bounds[1])
    return (math.log10(value) - (lo + hi) / 2) / ((hi - lo) / 2)


#: The table of gyro grades (module docstring), best first.
GYRO_GRADES: tuple[GyroGrade, ...] = (
    GyroGrade("strategic", "strategic-grade FOG or RLG",
              "FOG, RLG (marine, submarine, space)", (3e-5, 1e-3), (1e-4, 3e-3),
              "best instruments reach N, B of order 1e-4; inertial grade N < 0.001, "
              "B < 0.01 (Yazdi 1998; Passaro 2017; Groves 2013 ch. 4)"),
    GyroGrade("navigation", "navigation-grade FOG or RLG",
              "RLG, FOG (1 nmi/h aircraft and marine INS)", (3e-4, 1e-2), (1e-3, 5e-2),
              "Honeywell HG9900 N <= 0.002, B <= 0.003; GG1320AN N, B <= 0.0035; aviation-"
              "grade bias ~0.001..0.01 (Groves 2013 ch. 4)"),
    GyroGrade("tactical", "tactical-grade gyro", "FOG, RLG, high-end MEMS",
              (1e-3, 0.5), (3e-3, 30.0),
              "KVH/Emcore DSP-1750 N <= 0.012, B <= 0.1; Honeywell HG1700 N 0.125..0.3, "
              "B 1..10; tactical grade N 0.05..0.5, B 0.1..10 (Yazdi 1998; Passaro 2017)"),
    GyroGrade("industrial", "industrial/automotive MEMS gyro",
              "industrial and automotive MEMS", (0.05, 10.0), (0.5, 100.0),
              "ADIS16488 N 0.26, B 5.1; ADIS16448 N 0.66, B 14.5; ADIS16405 N 2.0, B 25; "
              "ADXRS150/300 N 3/6 (Analog Devices datasheets)"),
    GyroGrade("consumer", "consumer MEMS gyro", "consumer MEMS", (0.07, 6.0), (3.0, 1000.0),
              "MPU-6050, BMI160, L3G4200D N 0.3, 0.4, 1.8 (60 x noise density); rate grade "
              "N > 0.5, B 10..1000 (Yazdi 1998)"),
)

#: Envelope of N (deg/sqrt(h)) over every grade.
N_ENVELOPE: Bounds = (min(g.n_range[0] for g in GYRO_GRADES),
                      max(g.n_range[1] for g in GYRO_GRADES))
#: Envelope of B (deg/h) over every grade.
B_ENVELOPE: Bounds = (min(g.b_range[0] for g in GYRO_GRADES),
                      max(g.b_range[1] for g in GYRO_GRADES))

#: Each grade by its key.
GRADE_BY_KEY: dict[str, GyroGrade] = {g.key: g for g in GYRO_GRADES}


def grade_table() -> pd.DataFrame:
    """The grade table as a frame (one row per grade).

    Examples
    --------
    >>> grade_table().loc["tactical", ["N_low", "N_high", "B_low", "B_high"]].tolist()
    [0.001, 0.5, 0.003, 30.0]
    """
    rows = [{"grade": g.key, "label": g.label, "technology": g.technology,
             "N_low": g.n_range[0], "N_high": g.n_range[1], "B_low": g.b_range[0],
             "B_high": g.b_range[1], "anchors": g.anchors} for g in GYRO_GRADES]
    return pd.DataFrame(rows).set_index("grade")


def grades_of(N: float | None, B: float | None) -> tuple[tuple[str, ...], float]:
    """Grades holding (N, B), closest to a grade's middle first, and that distance."""
    hits = sorted((g.distance(N, B), i, g.key) for i, g in enumerate(GYRO_GRADES)
                  if g.contains(N, B))
    if not hits:
        return (), math.nan
    return tuple(k for _, _, k in hits), hits[0][0]
