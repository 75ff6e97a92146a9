"""The varied constructions' total conductance (``thermocal.calibration.envelope_total``)."""

from __future__ import annotations

from types import MethodType, SimpleNamespace

import numpy as np
import pandas as pd
import pytest

from thermocal.calibration.coordinates import FILM_RESISTANCE
from thermocal.calibration.envelope_total import (
    exterior_opaque_areas,
    total_conductance,
    total_conductance_sentences,
)
from thermocal.calibration.space import ParameterSpace
from thermocal.multizone.model import Building

ROOF, WALL = "construction/roof/resistance", "construction/wall/resistance"


def _building():
    """A roof of 100 m2 and walls of 80 m2 gross with 20 m2 of windows, a partition and a floor
    on the ground (neither counted); two zones of 300 and 150 m3."""
    surface = SimpleNamespace
    zone = SimpleNamespace
    building = SimpleNamespace(
        zones={
            "a": zone(volume=300.0, infiltration_ach=0.5, infiltration_group=None),
            "b": zone(volume=150.0, infiltration_ach=1.0, infiltration_group=None),
        },
        surfaces={
            "r": surface(name="r", boundary="outdoors", area=100.0, construction="roof"),
            "w1": surface(name="w1", boundary="outdoors", area=50.0, construction="wall"),
            "w2": surface(name="w2", boundary="outdoors", area=30.0, construction="wall"),
            "p": surface(name="p", boundary="zone", area=40.0, construction="wall"),
            "f": surface(name="f", boundary="ground", area=100.0, construction="slab"),
        },
        windows={
            "a": SimpleNamespace(surface="w1", area=12.0, window_type="clear"),
            "b": SimpleNamespace(surface="w2", area=8.0, window_type="clear"),
        },
    )
    building.net_area = MethodType(Building.net_area, building)  # the model's own net area
    return building


def _space():
    return ParameterSpace.from_parameters({ROOF: 4.0, WALL: 2.0}, default_range=0.5)


def _total(roof, wall):
    return 100.0 / (roof + FILM_RESISTANCE) + 60.0 / (wall + FILM_RESISTANCE)


def _draws_along_a_fixed_total(rng):
    """Draws of roof and wall resistance along the curve of the nominal total (the roof
    anywhere in part of its range, the walls compensating), and that total [W/K]."""
    roof = rng.uniform(2.5, 5.5, 4000)
    target = _total(4.0, 2.0)
    wall = 60.0 / (target - 100.0 / (roof + FILM_RESISTANCE)) - FILM_RESISTANCE
    keep = (wall > 1.0) & (wall < 3.0)
    return pd.DataFrame({ROOF: roof[keep], WALL: wall[keep]}), target


def test_net_opaque_areas_of_exterior_surfaces():
    assert exterior_opaque_areas(_building()) == {"roof": 100.0, "wall": 60.0}


def test_a_sum_the_data_fix_is_determined_while_its_parts_are_not():
    """Draws along the curve of a fixed total (the roof anywhere in its range, the walls
    compensating): the total's interval is a point, each resistance spans its range."""
    rng = np.random.default_rng(0)
    draws, target = _draws_along_a_fixed_total(rng)
    posterior = SimpleNamespace(samples=draws, determined=[])
    total = total_conductance(posterior, _space(), _building())["conduction"]
    assert total["elements"] == {"roof": 100.0, "wall": 60.0}
    assert total["median_W_per_K"] == pytest.approx(target, rel=1e-9)
    assert total["q95_W_per_K"] - total["q05_W_per_K"] < 1e-6
    assert total["nominal_W_per_K"] == pytest.approx(target)
    assert total["determined"] and total["separately_determined"] == []
    # the prior: uniform in each resistance over +-50 %
    prior = _total(rng.uniform(2, 6, 200_000), rng.uniform(1, 3, 200_000))
    assert total["prior_q05_W_per_K"] == pytest.approx(np.quantile(prior, 0.05), rel=0.01)
    assert total["prior_q95_W_per_K"] == pytest.approx(np.quantile(prior, 0.95), rel=0.01)
    (sentence,) = total_conductance_sentences({"conduction": total})
    assert "roof (100 m2), wall (60 m2)" in sentence and "the data fix the sum" in sentence


def test_a_sum_with_a_part_that_has_no_effect_is_not_determined():
    """The same narrow total, but the walls change the metric by no more than the estimation
    noise (the single parameters' effect-to-noise test): their narrow draws may be noise that
    looks like information, so the sum is not called determined (review, 2026-11-30)."""
    draws, _ = _draws_along_a_fixed_total(np.random.default_rng(0))
    summary = pd.DataFrame({"effect_to_noise": [30.0, 2.0]}, index=[ROOF, WALL])
    posterior = SimpleNamespace(samples=draws, determined=[], summary=summary)
    total = total_conductance(posterior, _space(), _building())["conduction"]
    assert total["q95_W_per_K"] - total["q05_W_per_K"] < 1e-6  # as narrow as before
    assert not total["determined"] and total["without_effect"] == [WALL]
    (sentence,) = total_conductance_sentences({"conduction": total})
    assert f"{WALL} change(s) the metric by no more than its estimation noise" in sentence
    summary.loc[WALL, "effect_to_noise"] = 9.0  # above the threshold (4): determined again
    assert total_conductance(posterior, _space(), _building())["conduction"]["determined"]


def test_the_prior_itself_is_not_determined():
    """Draws from the prior: the width fraction is 0.9 (the prior's own), not determined."""
    rng = np.random.default_rng(1)
    draws = pd.DataFrame({ROOF: rng.uniform(2, 6, 20_000), WALL: rng.uniform(1, 3, 20_000)})
    posterior = SimpleNamespace(samples=draws, determined=[])
    total = total_conductance(posterior, _space(), _building())["conduction"]
    assert total["width_fraction"] == pytest.approx(0.9, abs=0.03)
    assert not total["determined"]
    assert "not determined either" in total_conductance_sentences({"conduction": total})[0]


def test_nothing_to_add_with_one_resistance_or_every_one_determined():
    draws = pd.DataFrame({ROOF: [4.0, 4.1], WALL: [2.0, 2.1]})
    one = ParameterSpace.from_parameters({ROOF: 4.0}, default_range=0.5)
    assert total_conductance(SimpleNamespace(samples=draws, determined=[]), one, _building()) == {}
    both = total_conductance(
        SimpleNamespace(samples=draws, determined=[ROOF, WALL]), _space(), _building()
    )
    assert both["conduction"]["separately_determined"] == ["roof", "wall"]
    assert total_conductance_sentences(both) == []


def test_windows_count_with_their_u_value_and_area():
    """A window type's U-value (whole window) times its windows' area joins the sum."""
    win = "window/double/u_value"
    building = _building()
    for window in building.windows.values():
        window.window_type = "double"
    space = ParameterSpace.from_parameters({WALL: 2.0, win: 2.8}, default_range=0.5)
    draws = pd.DataFrame({WALL: [1.5, 2.0, 2.5], win: [2.0, 2.8, 3.6]})
    total = total_conductance(SimpleNamespace(samples=draws, determined=[]), space, building)
    total = total["conduction"]
    assert total["elements"] == {"wall": 60.0, "window double": 20.0}
    assert total["median_W_per_K"] == pytest.approx(60.0 / (2.0 + FILM_RESISTANCE) + 20.0 * 2.8)
    assert total["nominal_W_per_K"] == pytest.approx(60.0 / (2.0 + FILM_RESISTANCE) + 20.0 * 2.8)


def test_air_changes_and_everything_together():
    """Two zones' air change rates: their conductance rho c_p V n / 3600 (1200 J/(m3 K)), and
    with the roof the part of the heat loss coefficient the campaign varies."""
    a, b = "zone/a/infiltration_ach", "zone/b/infiltration_ach"
    space = ParameterSpace.from_parameters({ROOF: 4.0, a: 0.5, b: 1.0}, default_range=0.5)
    draws = pd.DataFrame({ROOF: [3.0, 4.0, 5.0], a: [0.4, 0.5, 0.6], b: [0.8, 1.0, 1.2]})
    totals = total_conductance(SimpleNamespace(samples=draws, determined=[]), space, _building())
    assert set(totals) == {"air", "all"}  # one construction: no conduction total of its own
    air = 1200.0 / 3600.0 * (300.0 * 0.5 + 150.0 * 1.0)
    assert totals["air"]["median_W_per_K"] == pytest.approx(air)
    assert totals["air"]["elements"] == {"a air": 300.0, "b air": 150.0}
    assert totals["all"]["median_W_per_K"] == pytest.approx(air + 100.0 / (4.0 + FILM_RESISTANCE))
    sentences = total_conductance_sentences(totals)
    assert "a air (300 m3), b air (150 m3)" in sentences[0]
    assert sentences[1].startswith("Everything varied together")


def test_a_group_and_an_uncertain_input():
    """A group's parameter is its members' mean rate, which scales each in proportion: its
    conductance is rho c_p (sum V r / mean r) n / 3600. A total whose part compensates an input
    integrated out is not called determined, however narrow."""
    building = _building()
    building.zones["a"].infiltration_group = building.zones["b"].infiltration_group = "flats"
    group = "infiltration/flats/ach"  # nominal: the mean of 0.5 and 1.0
    space = ParameterSpace.from_parameters({ROOF: 4.0, group: 0.75}, default_range=0.5)
    draws = pd.DataFrame({ROOF: [4.0, 4.0], group: [0.75, 0.75]})
    totals = total_conductance(SimpleNamespace(samples=draws, determined=[]), space, building)
    flow = (300.0 * 0.5 + 150.0 * 1.0) / 0.75
    assert totals["all"]["elements"]["flats air"] == 450.0
    assert totals["all"]["median_W_per_K"] == pytest.approx(
        1200.0 / 3600.0 * flow * 0.75 + 100.0 / (4.0 + FILM_RESISTANCE)
    )
    assert totals["all"]["determined"]  # a point: narrower than any prior
    confounded = SimpleNamespace(
        samples=draws, determined=[], uncertain=[{"compensates": {group: 0.83}}], in_situ={}
    )
    total = total_conductance(confounded, space, building)["all"]
    assert not total["determined"] and total["compensates_uncertain_input"] == [group]
    assert "compensate(s) an input integrated out" in total_conductance_sentences({"all": total})[0]
