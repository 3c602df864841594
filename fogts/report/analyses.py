"""The analyses behind the HTML report: the report's one link to the analysis packages.

Each result is computed for one rate axis on first use and kept, so sections that show the
same result (the ARMA table and the prediction, say) share one computation.  The section
builders in :mod:`fogts.report.sections` only render what this module returns.

The Allan and ARMA analyses are those of ``fogts allan`` and ``fogts select``
(:mod:`fogts.pipeline`), per axis ``i``:

* ``get_allan(i)`` / ``get_noise(i)`` / ``get_comparison(i)``:
  :func:`fogts.pipeline.analyse_allan_axis` of the raw rate (``kind``, ``taus``; the noise
  fit by the first of ``methods``, the others beside it);
* ``get_prepared(i)`` / ``get_selection(i)``: :func:`fogts.pipeline.analyse_selection` with
  the report's ``outliers``, ``detrend``, ``decimate`` and ``criterion``;
* ``get_dynamic_allan(i)``: :func:`fogts.allan.dynamic.dynamic_allan` (``davar_window_s``);
* ``get_compensation(i)``: :func:`fogts.startup.startup_workflow.startup_compensation` without EMD
  (``bias_average_s``).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from fogts.io.run import Run

__all__ = ["ReportContext", "analyse_run"]

if TYPE_CHECKING:
    from fogts.allan.misfit import FitCheck
    from fogts.allan.noise_compare import MethodComparison
    from fogts.allan.noise_model import NoiseModel
    from fogts.allan.readout import CurveReadout
    from fogts.allan.result import AllanResult
    from fogts.arma.selection import Selection
    from fogts.pipeline import AxisAllan, AxisSelection
    from fogts.preprocess.prepare import Prepared


@dataclass
class ReportContext:
    """What the sections share: the run, options, and results computed once."""

    run: Run
    options: dict[str, Any]
    quality: Any = None  # fogts.preprocess.hygiene.DataQuality
    allan_axes: dict[int, AxisAllan] = field(default_factory=dict)
    selections: dict[int, AxisSelection] = field(default_factory=dict)
    dynamic: dict[int, Any] = field(default_factory=dict)
    compensation: dict[int, Any] = field(default_factory=dict)

    allan_warnings: dict[int, list[Warning]] = field(default_factory=dict)

    def _allan_axis(self, i: int) -> AxisAllan:
        """The Allan analysis of axis ``i``, computed once; its warnings are raised again on
        every use, so the section that shows it has them whichever section computed it."""
        if i not in self.allan_axes:
            from fogts.pipeline import AllanSettings, analyse_allan_axis

            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                methods = self.options.get("methods", ("wls",))
                self.allan_axes[i] = analyse_allan_axis(self.run, i, AllanSettings(
                    kind=self.options["kind"], taus=self.options["taus"], method=methods[0],
                    compare_methods=tuple(methods[1:])))
            self.allan_warnings[i] = [w.message for w in caught
                                      if isinstance(w.message, Warning)]
        for message in self.allan_warnings[i]:
            warnings.warn(message, stacklevel=2)
        return self.allan_axes[i]

    def _selection(self, i: int) -> AxisSelection:
        if i not in self.selections:
            from fogts.pipeline import SelectSettings, analyse_selection

            o = self.options
            self.selections[i] = analyse_selection(self.run, self.quality, i, SelectSettings(
                outliers=o["outliers"], detrend=o["detrend"], decimate=o["decimate"],
                criterion=o["criterion"]))
        return self.selections[i]

    def get_allan(self, i: int) -> AllanResult:
        return self._allan_axis(i).result

    def get_noise(self, i: int) -> NoiseModel | None:
        return self._allan_axis(i).model

    def get_comparison(self, i: int) -> MethodComparison | None:
        return self._allan_axis(i).comparison

    def get_fit_check(self, i: int) -> FitCheck | None:
        return self._allan_axis(i).fit_check

    def get_fit_range(self, i: int) -> tuple[float | None, float | None] | None:
        return self._allan_axis(i).fit_range

    def get_readout(self, i: int) -> CurveReadout:
        return self._allan_axis(i).readout

    def get_prepared(self, i: int) -> Prepared:
        return self._selection(i).prepared

    def get_selection(self, i: int) -> Selection:
        return self._selection(i).selection

    def get_dynamic_allan(self, i: int) -> Any:
        """Windows of ``davar_window_s`` every quarter window (at least one sample); the
        report's estimator when it is oadev, mdev or ohdev, else oadev."""
        if i not in self.dynamic:
            from fogts.allan.dynamic import DynamicAllanResult, dynamic_allan

            window = float(self.options["davar_window_s"])
            step = max(window / 4.0, 1.0 / self.run.fs_hz)
            kind = self.options["kind"] if self.options["kind"] in ("oadev", "mdev", "ohdev") \
                else "oadev"
            res = dynamic_allan(self.run, axis=i, window_s=window, step_s=step,
                                kind=kind, glitches=self.quality)  # type: ignore[arg-type]
            assert isinstance(res, DynamicAllanResult)  # one axis was asked for
            self.dynamic[i] = res
        return self.dynamic[i]

    def get_compensation(self, i: int) -> Any:
        if i not in self.compensation:
            from fogts.startup.startup_workflow import startup_compensation

            self.compensation[i] = startup_compensation(
                self.run, axis=i, emd=False, average_s=self.options["bias_average_s"])
        return self.compensation[i]


def analyse_run(run: Run, quality: Any, options: dict[str, Any]) -> ReportContext:
    """The report's analyses of ``run``; its hygiene is assessed first (default gap policy)
    when ``quality`` is None, and the run it returns is the one analysed."""
    if quality is None:
        from fogts.preprocess.hygiene import assess_run

        run, quality = assess_run(run)
    return ReportContext(run=run, quality=quality, options=options)
