"""Forward model and identified heat against EnergyPlus 25.2 on the PNNL/DOE multifamily
prototype (20 zones, a building thermocal did not write; issue 28 item 7).

EnergyPlus runs ``tests/reference/identification_multifamily/multifamily_5A_FF_v25.idf`` free
float with its People/Lights/equipment schedules for the first eight days of January at
10-minute steps (:mod:`energyplus_twin`, about 3 s). The first day is left out of every metric.

* Forward: thermocal simulates the same file (with its loads); hourly RMSE and bias of each
  zone's air temperature.
* Identification: thermocal gets the file without the load objects (the true envelope) and
  EnergyPlus' zone air temperatures as perfect sensors, and identifies the heat with the exact
  inverse (default form); hourly NMBE and CV(RMSE) of the building's identified heat against
  the sensible gains EnergyPlus reports entering the zones, in all hours and in the
  identification's unoccupied hours; every zone sensed, then 15 of 20 (75 %: the attic, the
  breezeway and three flats float).

Measured 2026-11-25 on this period (January: ``tests/reference/identification_multifamily``),
with the bounds (a little above, so that a regression fails):

| check | measured | bound |
|---|---|---|
| forward, mean / worst zone hourly RMSE | 0.108 K / 0.153 K (breezeway) | 0.15 K / 0.25 K |
| forward, mean bias | -0.037 K | 0.08 K |
| all sensed, NMBE / CV(RMSE), all hours | -1.4 % / 11.1 % | 5 % / 15 % |
| all sensed, unoccupied hours | +4.5 % / 11.8 % | 7 % / 15 % |
| 15 of 20 sensed, all hours | -6.9 % / 13.6 % | 10 % / 17 % |
| 15 of 20 sensed, unoccupied hours | -1.3 % / 12.2 % | 5 % / 15 % |
| floating breezeway / attic, hourly RMSE | 0.16 K / 0.09 K | 0.3 K |

Re-measured 2026-11-28 (after the EnergyPlus-like shading): all sensed -0.9 % / 11.5 % in all
hours and +5.2 % / 12.6 % unoccupied; 15 sensed -6.6 % / 13.4 % and -1.0 % / 11.9 %. The
unoccupied +5.2 % is a delay, not one zone: every flat's identified heat is the true gains
smoothed and about 2-3 h late (-2.3 kW at 16-17 h while they rise, +2.2 kW at 23-00 h while
they fall), and the published unoccupied hours (weekday 20-04 h, weekends) sample only the
evening half; hence the 7 % bound of the default form, above the issue's 5 % target. The
delay is the composition of the gains: with the form the file declares step by step (last test)
these eight days give +0.8 % / 4.8 % in all hours and +1.1 % / 5.1 % unoccupied. With 15
sensed, the floating flats' -2.16 kW is offset by +1.29 kW in their sensed neighbours (heat
through the party walls into the cooler floating flats).

Without the building's own shadows (the front row shading the back row's breezeway facade)
the back-row flats ran +0.5 K warm (worst RMSE 0.72 K); without the ``Window`` objects the
file has no glazing at all. With 15 of 20 sensed, the three floating flats get no heat
(their gains, 3 x 0.36 kW, are not seen by any sensor): the NMBE of -6.9 % is that.

Runtime about 60 s on 2 shared cores, 18 s of processor time (EnergyPlus 5 s; one simulation
and two identifications, each with the shadows of the building on itself).
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from energyplus_twin import hourly_rmse_bias, make_twin_of, sensor_log, zone_fidelity

from conftest import requires_energyplus
from thermocal.errors import ThermocalInputError
from thermocal.identification.workflow import identify
from thermocal.multizone.idf import read_idf
from thermocal.multizone.idf.loads import declared_radiant_fraction
from thermocal.multizone.simulation import Simulation

pytestmark = [pytest.mark.slow, requires_energyplus]

IDF = (
    Path(__file__).resolve().parents[1]
    / "reference"
    / "identification_multifamily"
    / "multifamily_5A_FF_v25.idf"
)
DAYS = 8
STEPS_PER_HOUR = 6
STEP = f"{60 // STEPS_PER_HOUR}min"
UNSENSED = (
    "attic",
    "Breezeway",
    "living_unit3_BackRow_BottomFloor",
    "living_unit2_FrontRow_MiddleFloor",
    "living_unit1_BackRow_TopFloor",
)


@pytest.fixture(scope="module")
def twin(tmp_path_factory):
    if not IDF.is_file():
        pytest.skip(f"{IDF} is missing (run tests/reference/identification_multifamily/convert.py)")
    folder = tmp_path_factory.mktemp("multifamily_twin")
    twin = make_twin_of(IDF.read_text(), folder, DAYS, timesteps_per_hour=STEPS_PER_HOUR)
    twin.folder = folder
    return twin


def _identify(twin, zones, radiant_fraction=None, building=None):
    log, mapping = sensor_log(twin, zones)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = identify(
            twin.building if building is None else building,
            twin.weather,
            twin.metadata,
            log,
            mapping,
            # the sensors report each step's end: the first full step starts one step in
            start=twin.start + (twin.temperature.index[1] - twin.temperature.index[0]),
            end=twin.end,
            step=STEP,
            method="inverse",
            radiant_fraction=radiant_fraction,
        )
    every, empty = zone_fidelity(result, twin)
    return result, every, empty


def test_forward_free_float_against_energyplus(twin):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = read_idf(twin.folder / "twin.idf")  # the same file, with its loads
        result = Simulation(
            building,
            twin.weather,
            twin.metadata,
            step=STEP,
            start=twin.start,
            end=twin.end,
            store_surfaces=False,
        ).run(free_float=True)
    table = hourly_rmse_bias(result.air_temperature, twin.temperature)
    assert table["rmse"].mean() < 0.15, table
    assert table["rmse"].max() < 0.25, table
    assert abs(table["bias"].mean()) < 0.08, table


def test_identified_heat_all_zones_sensed(twin):
    _, every, empty = _identify(twin, list(twin.temperature.columns))
    assert abs(every["nmbe"]) <= 0.05
    assert every["cvrmse"] <= 0.15
    assert abs(empty["nmbe"]) <= 0.07
    assert empty["cvrmse"] <= 0.15


def test_identified_heat_three_quarters_sensed(twin):
    sensed = [z for z in twin.temperature.columns if z not in UNSENSED]
    result, every, empty = _identify(twin, sensed)
    sources = result.sources.set_index("zone")["source"]
    assert all(sources[z] == "float" for z in UNSENSED)
    assert abs(every["nmbe"]) <= 0.10
    assert every["cvrmse"] <= 0.17
    assert abs(empty["nmbe"]) <= 0.05
    assert empty["cvrmse"] <= 0.15
    # the unsensed zones without loads (breezeway, attic) float as EnergyPlus'
    for zone in ("Breezeway", "attic"):
        floating = result.floating_temperature[[zone]]
        error = hourly_rmse_bias(floating, twin.temperature[[zone]])
        assert float(error["rmse"].iloc[0]) < 0.3


def test_identified_heat_with_the_form_the_file_declares_step_by_step(twin):
    """The form of the identified heat taken from the file's own People/Lights/equipment
    objects step by step (``radiant_fraction="declared"`` on the file with its loads, which
    are then not simulated; the flats' gains are 60-88 % radiant as their composition changes,
    the occupants convective): the 2-3 h delay of the constant 0.6 form goes (hourly
    correlation 0.93 -> 0.99). The same as the envelope file given the form as a frame."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        loaded = read_idf(twin.folder / "twin.idf")  # the same file, with its loads
    zones = list(twin.temperature.columns)
    result, every, empty = _identify(twin, zones, radiant_fraction="declared", building=loaded)
    assert abs(every["nmbe"]) <= 0.03 and every["cvrmse"] <= 0.08, every
    assert abs(empty["nmbe"]) <= 0.03 and empty["cvrmse"] <= 0.08, empty
    assert every["r"] > 0.98
    assert any("the identified heat stands for them" in note for note in result.notes)
    step = pd.Timedelta(STEP)
    times = pd.date_range(twin.start, twin.end, freq=step, inclusive="left")
    form = pd.DataFrame(
        declared_radiant_fraction(loaded.idf_info, zones, times, step, fallback=0.6),
        index=times,
        columns=zones,
    )
    by_frame, _, _ = _identify(twin, zones, radiant_fraction=form)
    np.testing.assert_allclose(result.q_id.to_numpy(), by_frame.q_id.to_numpy(), atol=1e-6)


def test_floating_flats_keep_the_loads_the_file_declares(twin):
    """Declared form, 15 of 20 sensed: the three floating flats keep the file's load objects
    (no sensor, so no identified heat stands for them) and float as EnergyPlus' flats; their
    sensed neighbours' identified heat is then their own gains. Measured 2026-11-28: before,
    the flats floated without their gains (2.0-2.8 K cold) and the sensed zones' heat was
    +14.2 % / 15.2 % (heat drawn through the party walls); now +1.1 % / 4.9 % (unoccupied
    +1.5 % / 5.2 %), flats 0.06-0.08 K."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        loaded = read_idf(twin.folder / "twin.idf")
    sensed = [z for z in twin.temperature.columns if z not in UNSENSED]
    result, _, _ = _identify(twin, sensed, radiant_fraction="declared", building=loaded)
    own, quiet = zone_fidelity(result, twin, sensed)
    assert abs(own["nmbe"]) <= 0.03 and own["cvrmse"] <= 0.08, own
    assert abs(quiet["nmbe"]) <= 0.03 and quiet["cvrmse"] <= 0.08, quiet
    flats = [z for z in UNSENSED if z.startswith("living")]
    error = hourly_rmse_bias(result.floating_temperature[flats], twin.temperature[flats])
    assert error["rmse"].max() < 0.3, error
    assert (result.q_id[flats] == 0).all().all()
    assert any("keep them, simulated as known heat" in note for note in result.notes)


def test_load_objects_of_the_file_are_known_heat_unless_declared(twin):
    """Without ``declared`` the file's loads are simulated and the identified heat is what they
    do not account for (here almost nothing); the report says so and names the option."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        loaded = read_idf(twin.folder / "twin.idf")
    zones = list(twin.temperature.columns)
    result, _, _ = _identify(twin, zones, building=loaded)
    assert abs(result.q_id.sum(axis=1).mean()) < 0.02 * twin.gains.sum(axis=1).mean()
    assert any("radiant_fraction: declared" in note for note in result.notes)
    with pytest.raises(ThermocalInputError, match="declares none"):
        _identify(twin, zones, radiant_fraction="declared")  # the envelope file: no loads


def test_calibration_problem_takes_the_declared_form_too(twin):
    """The calibration's identification problem (one per campaign worker) with the mapping's
    ``identified_heat: {radiant_fraction: declared}`` gives the same identified heat as
    :func:`identify`, and a fingerprint that tells the form apart."""
    from thermocal.identification.problem import problem_from_measurements

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        loaded = read_idf(twin.folder / "twin.idf")
    zones = list(twin.temperature.columns)
    log, mapping = sensor_log(twin, zones)
    mapping["identified_heat"] = {"radiant_fraction": "declared"}
    common = dict(
        start=twin.start + (twin.temperature.index[1] - twin.temperature.index[0]),
        end=twin.end,
        step=STEP,
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        problem, _ = problem_from_measurements(
            loaded, twin.weather, twin.metadata, log, mapping, **common
        )
        heat = problem.run().heat
        direct = identify(
            loaded, twin.weather, twin.metadata, log, mapping, method="inverse", **common
        )
    np.testing.assert_allclose(heat.to_numpy(), direct.q_id[heat.columns].to_numpy(), atol=1e-6)
    constant = dict(mapping, identified_heat={"radiant_fraction": 0.6})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        other, _ = problem_from_measurements(
            twin.building, twin.weather, twin.metadata, log, constant, **common
        )
    assert problem.fingerprint() != other.fingerprint()
