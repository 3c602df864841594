"""The recordings the batch tests run on: 20 files, 3 of them bad, and a stand-in analysis.

Truth: the good files are white noise of known standard deviation sigma (deg/h) at 10 Hz, so
the angle random walk is N = sigma / sqrt(fs) / 60 deg/sqrt(h) (IEEE Std 952-1997 Annex C;
DESIGN.md conversion).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from fogts.batch import RUN_JSON_VERSION, SUMMARY_COLUMNS, BatchOptions, RunOutcome

N_GOOD, FS, SIGMA = 17, 10.0, 0.8
N_SAMPLES = 1200
BAD = {
    "bad_text.csv": ("time,rate\n0.0,1.0\n0.1,oops\n0.2,3.0\n0.3,4.0\n", "non-numeric"),
    "bad_short.csv": ("time,rate\n0.0,1.0\n0.1,2.0\n", "at least"),
    "bad_time.csv": ("time,rate\n" + "".join(f"{(i * 7) % 5}.0,{i}.5\n" for i in range(40)),
                     "time"),
}


def make_files(folder: Path) -> list[Path]:
    """Write the 17 good and 3 bad recordings into ``folder``."""
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for k in range(N_GOOD):
        rng = np.random.default_rng(100 + k)
        t = np.arange(N_SAMPLES) / FS
        rate = 0.3 + rng.normal(0.0, SIGMA, N_SAMPLES)
        p = folder / f"run_{k:02d}.csv"
        np.savetxt(p, np.c_[t, rate], delimiter=",", header="time,rate", comments="",
                   fmt="%.6f")
        paths.append(p)
    for name, (text, _) in BAD.items():
        p = folder / name
        p.write_text(text)
        paths.append(p)
    return sorted(paths)


def check_summary(frame: pd.DataFrame, folder: Path) -> None:
    """The summary of a batch over the files of :func:`make_files` in ``folder``."""
    assert list(frame.columns) == list(SUMMARY_COLUMNS)
    assert len(frame) == 20
    assert frame["file"].is_unique
    assert sorted(Path(f).name for f in frame["file"]) == sorted(
        p.name for p in folder.glob("*.csv"))
    ok, bad = frame[frame["status"] == "ok"], frame[frame["status"] == "error"]
    assert len(ok) == 17 and len(bad) == 3
    for _, row in bad.iterrows():
        expect = BAD[Path(row["file"]).name][1]
        assert expect in str(row["error"]), (row["file"], row["error"])
        assert pd.isna(row["N"])
    assert (ok["error"].fillna("") == "").all()
    assert (ok["n"] == N_SAMPLES).all()
    np.testing.assert_allclose(ok["fs_hz"].astype(float), FS, rtol=1e-9)
    # ARW of white noise: N = sigma / sqrt(fs) / 60; 1200 samples give the fit a few %
    n_true = SIGMA / np.sqrt(FS) / 60.0
    np.testing.assert_allclose(ok["N"].astype(float), n_true, rtol=0.15)
    assert (ok["N_stderr"].astype(float) > 0).all()
    assert ok["selected"].notna().all()
    assert np.isfinite(ok["aic"].astype(float)).all()
    assert ok["white"].notna().all()


def fake_analysis(file: str, options: BatchOptions) -> RunOutcome:
    """A picklable stand-in analysis: fails for names containing 'bad'."""
    if "bad" in Path(file).name:
        raise RuntimeError("boom in " + Path(file).name)
    row = dict.fromkeys(SUMMARY_COLUMNS)
    row.update(file=file, axis="rate", n=1, status="ok", error="")
    return RunOutcome(file=file, status="ok", error="", rows=(row,),
                      document={"version": RUN_JSON_VERSION, "rows": [row]})
