"""Identified heat against EnergyPlus 25.2 on a twin of NREL's 5ZoneAirCooled (a building
thermocal did not write).

EnergyPlus runs the free-floating office with its People/Lights/ElectricEquipment schedules at
5-minute steps over the first ten days of January (:mod:`energyplus_twin`, about 2 s); its zone
air temperatures are perfect sensors, and thermocal, given the file without the loads (the true
envelope), identifies the heat with the exact inverse. The building's identified heat is
compared hour by hour (first day left out) with the sensible gains EnergyPlus reports entering
the zones, in all hours and in the method's unoccupied hours.

Measured 2026-11-25 (this period; January in ``tests/reference/identification_5zone``), NMBE /
CV(RMSE), and the bounds (a little above, so that a regression fails; the unoccupied-hour bounds
fail with the former star long-wave network, which gave +13.8 % / 21.8 % and +10.9 % / 18.0 %):

| case | all hours | bound | unoccupied hours | bound |
|---|---|---|---|---|
| 6 of 6 sensed, default form | -0.1 % / 4.8 % | 5 % / 15 % | +11.1 % / 20.2 % | 12.5 % / 21 % |
| 5 of 6 sensed, plenum floats | -0.2 % / 4.0 % | 5 % / 15 % | +7.9 % / 16.4 % | 9.5 % / 17.5 % |
| 6 of 6, the paper's form (all into the air) | about -26 % / 46 % | NMBE < -15 % | - | - |

The floating plenum's simulated temperature: hourly RMSE about 0.13-0.18 K against EnergyPlus
(bound 0.5 K). Runtime about 13 s (EnergyPlus 2 s, four identifications).

The unoccupied-hour target of issue 28 (|NMBE| <= 5 %, CV(RMSE) <= 15 %) is not met yet: what
is left is mostly the return plenum (about +75 W of the +95 W at night with every zone sensed),
whose temperature swings about 0.1-0.2 K more than EnergyPlus' over the day (see
docs/identification.md).
"""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd
import pytest
from energyplus_twin import ZONES, fidelity, make_twin, sensor_log

from conftest import requires_energyplus, shared_data_path
from thermocal.identification.workflow import identify

pytestmark = [pytest.mark.slow, requires_energyplus]

DAYS = 10


@pytest.fixture(scope="module")
def twin(tmp_path_factory):
    folder = shared_data_path("energyplus_reference")
    return make_twin(folder, tmp_path_factory.mktemp("twin5zone"), DAYS)


def _identify(twin, zones, **kwargs):
    log, mapping = sensor_log(twin, zones)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = identify(
            twin.building,
            twin.weather,
            twin.metadata,
            log,
            mapping,
            start=twin.start,
            end=twin.end,
            method="inverse",
            **kwargs,
        )
    q = result.q_id
    truth = twin.gains.reindex(q.index)
    keep = q.index >= q.index[0] + pd.Timedelta("1D")
    every = fidelity(q[keep], truth[keep])
    empty = fidelity(q[keep], truth[keep], result.unoccupied_mask()[keep])
    return result, every, empty


def test_identified_heat_matches_energyplus_gains_all_zones_sensed(twin):
    _, every, empty = _identify(twin, ZONES)
    assert abs(every["nmbe"]) <= 0.05
    assert every["cvrmse"] <= 0.15
    assert abs(empty["nmbe"]) <= 0.125
    assert empty["cvrmse"] <= 0.21
    # the paper's form (all of the heat into the air) misses the radiant gains
    _, paper, _ = _identify(twin, ZONES, radiant_fraction=0.0, feedback="air")
    assert paper["nmbe"] < -0.15


def test_identified_heat_with_the_plenum_unsensed_floating(twin):
    sensed = [z for z in ZONES if z != "PLENUM-1"]
    result, every, empty = _identify(twin, sensed)
    assert result.sources.set_index("zone").loc["PLENUM-1", "source"] == "float"
    assert (result.q_id["PLENUM-1"] == 0.0).all()
    assert abs(every["nmbe"]) <= 0.05
    assert every["cvrmse"] <= 0.15
    assert abs(empty["nmbe"]) <= 0.095
    assert empty["cvrmse"] <= 0.175
    # the floating plenum's simulated temperature follows EnergyPlus'
    floating = result.floating_temperature["PLENUM-1"]
    reference = twin.temperature["PLENUM-1"].reindex(floating.index)
    hourly = (floating - reference).groupby(floating.index.floor("1h")).mean()
    assert float(np.sqrt((hourly**2).mean())) < 0.5
