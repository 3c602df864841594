"""AR and MA roots against statsmodels' ArmaProcess (to 1e-10)."""

from __future__ import annotations

import numpy as np
import pytest

from fogts.arma.diagnostics import (
    arma_roots,
)


@pytest.mark.parametrize(("ar", "ma"), [([0.5, -0.3], [0.4]), ([0.9, -0.5, 0.1], [-0.4]),
                                         ([1.2, -0.8], [0.5, 0.3])])
def test_roots_equal_statsmodels(ar: list[float], ma: list[float]) -> None:
    from statsmodels.tsa.arima_process import ArmaProcess

    ref = ArmaProcess(ar=np.r_[1.0, -np.asarray(ar)], ma=np.r_[1.0, ma])
    r = arma_roots(ar, ma)
    assert np.allclose(np.sort_complex(r.ar), np.sort_complex(ref.arroots), atol=1e-10)
    assert np.allclose(np.sort_complex(r.ma), np.sort_complex(ref.maroots), atol=1e-10)
    assert np.allclose(np.sort(r.ar_modulus), np.sort(np.abs(ref.arroots)), atol=1e-10)
    assert np.allclose(np.sort_complex(r.ar_inverse), np.sort_complex(1 / ref.arroots),
                       atol=1e-10)
    assert r.stationary == bool(ref.isstationary) and r.invertible == bool(ref.isinvertible)
    d = r.to_dict()
    assert set(d) == {"ar", "ma", "ar_modulus", "ma_modulus", "ar_inverse", "ma_inverse",
                      "stationary", "invertible"}


def test_roots_flag_nonstationary_and_noninvertible() -> None:
    r = arma_roots([1.2], [-1.5])
    assert not r.stationary and not r.invertible
    assert r.ar_radius == pytest.approx(1.2) and r.ma_radius == pytest.approx(1.5)
