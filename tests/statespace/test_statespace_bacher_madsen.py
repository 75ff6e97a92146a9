"""External data: the Bacher & Madsen (2011) FlexHouse PRBS experiment (CTSM-R example data).

The reference log-likelihoods in ``bacher_madsen_loglikes.json`` were produced by
``reference_bacher_madsen.py`` (8 random starts per model plus warm starts); the published
table of Bacher & Madsen could not be obtained, see docs/bacher-madsen-selection.md. Here single
fits from the declared start values must reach those optima, and the likelihood-ratio tests of
the first two selection steps must come out as recorded.
"""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
import pytest

from thermocal.statespace import RCModel
from thermocal.statespace.diagnostics import likelihood_ratio_test

REPO = Path(__file__).resolve().parents[2]
REFERENCE = json.loads((Path(__file__).parent / "bacher_madsen_loglikes.json").read_text())


def model(name: str) -> RCModel:
    return RCModel.from_yaml(REPO / "examples" / "models" / f"{name}.yaml")


_CACHE: dict = {}


@pytest.fixture
def prbs(shared_data):
    path = shared_data("bacher_madsen_2011_prbs", "inputPRBS1.csv")
    if "data" not in _CACHE:
        _CACHE["data"] = pd.read_csv(path, sep=";")
    return _CACHE["data"]


@pytest.fixture
def fits(prbs):
    if "fits" not in _CACHE:  # fitted once for the module
        _CACHE["fits"] = {
            name: model(name).fit(prbs, time_column="t", time_unit="h")
            for name in ("Ti", "TiTh", "TiTeTh")
        }
    return _CACHE["fits"]


def test_data_layout(prbs):
    assert list(prbs.columns) == ["t", "Ta", "Ps", "Ph", "yTi"]
    assert len(prbs) == 1691
    assert prbs["t"].diff().dropna().round(6).eq(round(5 / 60, 6)).all()


@pytest.mark.parametrize("name", ["Ti", "TiTh", "TiTeTh"])
def test_single_fit_reaches_the_reference_optimum(fits, name):
    res = fits[name]
    assert res.converged
    assert res.nobs == 1691
    assert res.n_free == REFERENCE["n_free"][name]
    assert res.loglike == pytest.approx(REFERENCE["loglike"][name], abs=0.05)


def test_selection_steps_and_physics(fits):
    first = likelihood_ratio_test(fits["Ti"], fits["TiTh"])
    second = likelihood_ratio_test(fits["TiTh"], fits["TiTeTh"])
    assert first.df == 4 and first.pvalue < 1e-10
    assert second.df == 4 and second.pvalue < 1e-10
    assert REFERENCE["path"][:3] == ["Ti", "TiTh", "TiTeTh"]
    # heat loss coefficient of the lightweight test building: envelope path Rie + Rea [K/kW]
    p = fits["TiTeTh"].params
    hlc = 1000.0 / (p["Rie"] + p["Rea"])  # [W/K]
    assert 100.0 < hlc < 300.0
    # the one-state model's Ria is the total resistance seen from the interior
    assert fits["Ti"].params["Ria"] == pytest.approx(p["Rie"] + p["Rea"], rel=0.15)


def test_tighter_stall_tolerance_reaches_the_polished_optimum(fits, prbs):
    """TiTeTh's maximum lies on a flat ridge (Ch -> 0 with Rih, |r| = 0.999): the default stall
    rule (gain < 1e-3 over 10 iterations) stops about 0.02 short of it. With
    stall_tolerance=1e-5 the fit reaches the optimum found by running scipy's BFGS on from the
    default result until its gradient test (gtol 1e-9) stops it: 5432.5479."""
    tight = model("TiTeTh").fit(prbs, time_column="t", time_unit="h", stall_tolerance=1e-5)
    assert tight.converged
    assert tight.loglike == pytest.approx(5432.5479, abs=2e-3)
    assert tight.loglike > fits["TiTeTh"].loglike


#: The poorer of TiTmTeTh's two optima on the PRBS data (log-likelihood 5445.78, where
#: `thermocal fit` of the model file stopped, "converged": three starts agreed on it): the
#: internal mass ``Tm`` light and quiet, the envelope ``Te`` heavy and noisy. The better optimum
#: (5448.32, found by `select` from TiTmTeThRia's estimates) has the two states' roles exchanged.
TITMTETH_POOR_OPTIMUM = {
    "Ci": 0.97759, "Cm": 0.43173, "Ce": 3.47049, "Ch": 0.0031, "Rih": 46.80845, "Rim": 1.36927,
    "Rie": 1.26484, "Rea": 4.23748, "Aw": 5.67401, "sigma_i": 0.01118, "sigma_m": 0.00077,
    "sigma_e": 0.44408, "sigma_h": 0.05274, "e_std": 0.0027, "Ti0": 21.15853, "Tm0": 22.74869,
    "Te0": 16.01153, "Th0": 0.01,
}  # fmt: skip


def test_fit_started_at_a_poor_optimum_finds_the_exchanged_one_or_says_so(prbs):
    """Issue 29, item 1 in another form: started at the poorer optimum, the declared start and
    a random start agreed there and the fit said converged (5445.78) although 5448.32 exists.
    The state-exchange starts reach the better optimum, confirmed by two of them."""
    start = model("TiTmTeTh").with_parameters(TITMTETH_POOR_OPTIMUM)
    res = start.fit(prbs, time_column="t", time_unit="h", n_starts=2, n_jobs=2)
    assert res.loglike > 5448.2  # before: 5445.78, converged
    assert res.converged and res.agreement["n_best"] >= 2
    assert res.params["Cm"] > res.params["Ce"]  # the mass is now the heavy state


def test_heat_loss_profiles_in_parallel_equal_the_serial_ones(fits, monkeypatch):
    """`heat_loss_coefficients` computes each side of each profile in its own process; the
    intervals, the profile points' effects (flags, convergence) are those of the profile in
    one piece, bit for bit. On this data Ti's lower side evaluates the profile at the estimate
    (its first step crosses the threshold), which moves the point the upper side starts from:
    the upper side is then computed again from it."""
    import copy

    from thermocal.statespace import results

    names = ["Ti", "TiTh"]
    parallel = {n: copy.deepcopy(fits[n]) for n in names}
    serial = {n: copy.deepcopy(fits[n]) for n in names}
    got = results.heat_loss_coefficients(parallel, profile=names, n_jobs=2)
    for n in names:
        assert got[n] == serial[n].heat_loss_coefficient()
        assert got[n]["interval"] == "profile"
        assert parallel[n].converged == serial[n].converged
        assert parallel[n].flags == serial[n].flags
    monkeypatch.setattr(results, "_HLC_FITS", {"Ti": fits["Ti"]})
    lower = results._hlc_side_worker(("Ti", -1.0, 0.05, None))
    assert results._centre_moved(fits["Ti"], lower[3]) is not None
