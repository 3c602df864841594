"""The analyses behind the HTML report: the report's one link to the analysis packages.

Each result is computed for one rate axis on first use and kept, so sections that show the
same result (the ARMA table and the prediction, say) share one computation.  The section
builders in :mod:`fogts.report.sections` only render what this module returns.

The chain, per axis ``i``:

* ``get_prepared(i)``: :func:`fogts.preprocess.prepare.prepare` with the report's
  ``outliers``, ``detrend`` and ``decimate`` (the series the ARMA analysis sees);
* ``get_allan(i)``: :func:`fogts.allan.allan_deviation` of the raw rate (``kind``, ``taus``);
* ``get_noise(i)``: :func:`fogts.allan.noise.fit_noise` of that curve;
* ``get_selection(i)``: :func:`fogts.arma.select_arma` of the prepared series (``criterion``);
* ``get_dynamic_allan(i)``: :func:`fogts.allan.dynamic.dynamic_allan` (``davar_window_s``);
* ``get_compensation(i)``: :func:`fogts.startup.startup_workflow.startup_compensation` without EMD
  (``bias_average_s``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from fogts.io.run import Run


@dataclass
class _Context:
    """What the sections share: the run, options, and results computed once."""

    run: Run
    options: dict[str, Any]
    quality: Any = None  # fogts.preprocess.hygiene.DataQuality
    prepared: dict[int, Any] = field(default_factory=dict)
    allan: dict[int, Any] = field(default_factory=dict)
    noise: dict[int, Any] = field(default_factory=dict)
    selection: dict[int, Any] = field(default_factory=dict)
    dynamic: dict[int, Any] = field(default_factory=dict)
    compensation: dict[int, Any] = field(default_factory=dict)

    def get_prepared(self, i: int) -> Any:
        if i not in self.prepared:
            from fogts.preprocess.prepare import prepare

            o = self.options
            self.prepared[i] = prepare(self.run, axis=i, outliers=o["outliers"],
                                       detrend=o["detrend"], decimate=o["decimate"])
        return self.prepared[i]

    def get_allan(self, i: int) -> Any:
        if i not in self.allan:
            from fogts.allan import allan_deviation

            self.allan[i] = allan_deviation(self.run, axis=i, kind=self.options["kind"],
                                            taus=self.options["taus"])
        return self.allan[i]

    def get_noise(self, i: int) -> Any:
        if i not in self.noise:
            from fogts.allan.noise import fit_noise

            self.noise[i] = fit_noise(self.get_allan(i))
        return self.noise[i]

    def get_selection(self, i: int) -> Any:
        if i not in self.selection:
            from fogts.arma import select_arma

            self.selection[i] = select_arma(self.get_prepared(i),
                                            criterion=self.options["criterion"])
        return self.selection[i]

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
                                kind=kind)  # type: ignore[arg-type]
            assert isinstance(res, DynamicAllanResult)  # one axis was asked for
            self.dynamic[i] = res
        return self.dynamic[i]

    def get_compensation(self, i: int) -> Any:
        if i not in self.compensation:
            from fogts.startup.startup_workflow import startup_compensation

            self.compensation[i] = startup_compensation(
                self.run, axis=i, emd=False, average_s=self.options["bias_average_s"])
        return self.compensation[i]


def _analyses(run: Run, quality: Any, options: dict[str, Any]) -> _Context:
    """The report's analyses of ``run``; its hygiene is assessed first (default gap policy)
    when ``quality`` is None, and the run it returns is the one analysed."""
    if quality is None:
        from fogts.preprocess.hygiene import assess_run

        run, quality = assess_run(run)
    return _Context(run=run, quality=quality, options=options)
