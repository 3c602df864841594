"""Tests of fogts.arma.spec: the ARMA parameter type and its one coercion."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

from fogts.arma.spec import ArmaSpec
from fogts.errors import DataError


def test_from_any_reads_every_form_alike() -> None:
    expected = ArmaSpec(ar=(0.9,), ma=(0.2,), sigma2=0.5)
    fit = SimpleNamespace(ar=np.array([0.9]), ma=np.array([0.2]),
                          params=pd.Series({"ar.L1": 0.9, "ma.L1": 0.2, "sigma2": 0.5}))
    forms = [
        expected,
        fit,                                               # an ArmaFit: ar, ma, params
        SimpleNamespace(ar=[0.9], ma=[0.2], sigma2=0.5),   # a Candidate: ar, ma, sigma2
        SimpleNamespace(best=fit),                         # a Selection
        {"ar": [0.9], "ma": [0.2], "sigma2": 0.5},
        {"ar.L1": 0.9, "ma.L1": 0.2, "sigma2": 0.5},
        {"params": {"ar.L1": 0.9, "ma.L1": 0.2, "sigma2": 0.5}},
        SimpleNamespace(params={"ar.L1": 0.9, "ma.L1": 0.2, "sigma2": 0.5}),
        ([0.9], [0.2], 0.5),
        "ar=0.9;ma=0.2;sigma2=0.5",
    ]
    for form in forms:
        assert ArmaSpec.from_any(form) == expected, form
    assert ArmaSpec.from_any(expected) is expected


def test_from_any_lags_and_constant() -> None:
    spec = ArmaSpec.from_any({"ar.L2": 0.1, "ma.L1": 0.2, "sigma2": 1, "const": 3.0})
    assert spec.ar == (0.0, 0.1) and spec.ma == (0.2,) and spec.const == 3.0
    assert ArmaSpec.from_any(((0.5,), (), 1.0, 2.0)).const == 2.0
    fit = SimpleNamespace(ar=[0.5], ma=[], params={"sigma2": 1.0, "const": -1.5})
    assert ArmaSpec.from_any(fit).const == -1.5
    assert ArmaSpec.parse("ar=0.5;ma=0.1,0.2;sigma2=1;const=0").to_dict()["order"] == [1, 2]


def test_burn_in_and_radius() -> None:
    spec = ArmaSpec(ar=(0.5,), sigma2=1.0)
    assert spec.ar_radius == pytest.approx(0.5)
    assert spec.burn_in() == 40  # ceil(log(1e-12) / log(0.5))
    assert ArmaSpec(sigma2=1.0).burn_in() == 0
    assert ArmaSpec(ar=(0.9999999,), sigma2=1.0).burn_in() == 1_000_000  # the cap


def test_errors() -> None:
    with pytest.raises(DataError, match="not stationary"):
        ArmaSpec(ar=(1.2,))
    with pytest.raises(DataError, match="sigma2 must be a finite number > 0"):
        ArmaSpec(sigma2=-1.0)
    with pytest.raises(DataError, match="ARMA coefficients must be finite"):
        ArmaSpec(ar=(float("nan"),))
    with pytest.raises(DataError, match="const must be finite"):
        ArmaSpec(const=float("inf"))
    with pytest.raises(DataError, match="arma needs sigma2"):
        ArmaSpec.parse("ar=0.5")
    with pytest.raises(DataError, match="arma key must be one of"):
        ArmaSpec.parse("phi=0.5;sigma2=1")
    with pytest.raises(DataError, match="arma must look like"):
        ArmaSpec.parse("0.5")
    with pytest.raises(DataError, match="arma ar must be numbers"):
        ArmaSpec.parse("ar=x;sigma2=1")
    with pytest.raises(DataError, match="arma sigma2 must be one number"):
        ArmaSpec.parse("sigma2=1,2")
    with pytest.raises(DataError, match="ARMA mapping keys must be"):
        ArmaSpec.from_any({"ar": [0.5], "sigma": 1})
    with pytest.raises(DataError, match="needs 'sigma2'"):
        ArmaSpec.from_any({"ar": [0.5]})
    with pytest.raises(DataError, match="ARMA params need 'sigma2'"):
        ArmaSpec.from_any({"ar.L1": 0.5})
    with pytest.raises(DataError, match="has no sigma2"):
        ArmaSpec.from_any(SimpleNamespace(ar=[0.5], ma=[], params={}))
    with pytest.raises(DataError, match="model must be an ArmaFit"):
        ArmaSpec.from_any(3.0)
    with pytest.raises(DataError, match="the selection has no selected model"):
        ArmaSpec.from_any(SimpleNamespace(best=None))
    with pytest.raises(DataError, match="an ARMA tuple must be"):
        ArmaSpec.from_any(([0.5], 1.0))
    with pytest.raises(DataError, match="is not a lag like ar.L1"):
        ArmaSpec.from_any({"ar.L0": 0.5, "sigma2": 1.0})
    with pytest.raises(DataError, match="ARMA parameter sigma2 must be a number"):
        ArmaSpec.from_any({"ar.L1": 0.5, "sigma2": "big"})
