"""Forward selection: an accepted model whose re-polish ends ineligible is withdrawn."""

from __future__ import annotations

from contextlib import contextmanager
from types import SimpleNamespace

import numpy as np
import pandas as pd

from thermocal.statespace import estimation, selection

#: Scripted optima: (n_free, log-likelihood, converged, physical parameters at a bound).
#: "TiTh" as first fitted is converged inside its bounds; re-polished from the estimates of its
#: extension it reaches 25 > 20 with Rih on its bound and not converged (the shape of the
#: ASHRAE 140 Case 600 free-float selection of `thermocal select --bounds family`).
FIRST = {"Ti": (2, 0.0, True, []), "TiTh": (3, 20.0, True, []), "TiThTe": (4, 30.0, True, [])}
REPOLISHED = {"Ti": (2, 0.0, True, []), "TiTh": (3, 25.0, False, ["Rih"])}


class _Model:
    """Stand-in for ``RCModel`` whose ``fit`` returns scripted results (no optimisation)."""

    def __init__(self, name: str):
        self.name = name
        self.free_parameter_names = ["Ci", "Rih", "Ria", "Ce"][: FIRST[name][0]]

    def structure(self):
        return SimpleNamespace(roles={"Ci": {"capacity"}, "Rih": {"resistance"},
                                      "Ria": {"resistance"}, "Ce": {"capacity"}})  # fmt: skip

    def fit(self, data, *, warm_start=None, **kw):
        # a dict start is the re-polish from an extension's estimates
        n_free, loglike, converged, at_bound = (
            REPOLISHED if isinstance(warm_start, dict) else FIRST
        )[self.name]
        return SimpleNamespace(
            model=self, n_free=n_free, nobs=100, loglike=loglike, converged=converged,
            at_bound=list(at_bound), flags=[], agreement={"n_best": 2}, expected_gain=np.nan,
            params=pd.Series(1.0, index=self.free_parameter_names),
        )  # fmt: skip


def test_accepted_model_ineligible_after_its_repolish_is_withdrawn(monkeypatch):
    """Ti -> TiTh is accepted (LR statistic 40, TiTh converged inside its bounds); TiTh's
    re-polish from TiThTe finds a better optimum, not converged with Rih on its bound. Before,
    TiTh stayed accepted and selected with its row reading "not converged; at bound: Rih"; now
    it is withdrawn (not accepted, the row says why) and the selection steps back to Ti."""

    @contextmanager
    def no_pool(problems=(), n_jobs=None):
        yield None

    monkeypatch.setattr(estimation, "shared_pool", no_pool)
    monkeypatch.setattr(selection, "_candidate_problems", lambda *a: [])
    models = {name: _Model(name) for name in FIRST}
    result = selection.forward_selection(
        models, {"Ti": ["TiTh"], "TiTh": ["TiThTe"]}, pd.DataFrame(), start="Ti"
    )
    table = result.table
    assert result.path == ["Ti"]
    first = table[(table["model"] == "TiTh") & (table["iteration"] == 1)].iloc[0]
    # the row shows the re-polished fit (its test against Ti: 2 * 25), withdrawn
    assert first["statistic"] == 50.0 and first["selected"]
    assert not first["accepted"] and not first["converged"] and first["at_bound"] == "Rih"
    assert "re-polished from an extension" in first["status"]
    assert "no longer eligible after the re-polish" in first["status"]
    assert not table["accepted"].iloc[1:].any()
    ext = table[table["model"] == "TiThTe"].iloc[0]
    assert "not accepted after its re-polish" in ext["status"]
