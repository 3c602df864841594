"""Files for the io tests: a writer that keeps the bytes as given and a small CSV."""

from __future__ import annotations

from pathlib import Path

import numpy as np


def write_file(tmp_path: Path, name: str, text: str | bytes) -> Path:
    """``tmp_path / name`` holding ``text`` exactly (no newline translation)."""
    p = tmp_path / name
    if isinstance(text, bytes):
        p.write_bytes(text)
    else:
        p.write_text(text, encoding="utf-8", newline="")
    return p


def csv_text(n: int = 50, fs: float = 10.0, sep: str = ",", header: str = "time,rate,T") -> str:
    """``n`` rows of time, a seeded normal rate and a slowly rising temperature."""
    rng = np.random.default_rng(1)
    rows = [header.replace(",", sep)]
    for i in range(n):
        rows.append(sep.join([f"{i / fs:.4f}", f"{rng.normal():.6f}", f"{25 + i * 0.01:.3f}"]))
    return "\n".join(rows) + "\n"
