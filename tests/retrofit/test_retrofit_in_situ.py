"""In-situ U-values in the retrofit configuration (``in_situ:``,
:mod:`thermocal.retrofit.in_situ`): what becomes the prior of a component's own factor, and the
clear errors of a log a user gets wrong. The EnergyPlus twin with the plate is in
``test_retrofit_energyplus_twin.py::test_twin_with_an_in_situ_wall_u_value``."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from thermocal.errors import ThermocalInputError
from thermocal.io.envelope import read_envelope
from thermocal.retrofit.config import parse_config
from thermocal.retrofit.correction import (
    correction_groups,
    group_label,
    group_priors,
    scaled_envelope,
)
from thermocal.retrofit.in_situ import in_situ_priors, measure_in_situ
from thermocal.retrofit.model import build_fifth_order_model

REF = Path(__file__).resolve().parents[1] / "reference" / "retrofit_energyplus_house"
LOG = REF / "heat_flux_north_wall.csv"
COLUMNS = {"heat_flux": "q_W_m2", "temp_in": "Ti", "temp_out": "Te"}


def _config(in_situ: dict, tmp_path: Path):
    return parse_config(
        {
            "building": str(REF / "building.yaml"),
            "measurements": {"file": "m.csv", "columns": {"temp_out": "Te"}},
            "weather": {"file": "w.epw"},
            "in_situ": in_situ,
        },
        base_dir=tmp_path,
        source="config.yaml",
    )


@pytest.fixture(scope="module")
def building():
    return read_envelope(REF / "building.yaml")


def test_a_measured_component_gets_its_own_factor_and_prior(building, tmp_path):
    cfg = _config({"walls": {"file": str(LOG), "columns": COLUMNS}}, tmp_path)
    measured = measure_in_situ(cfg, building, 1.0)
    wall = measured["walls"]
    assert wall.described_u == pytest.approx(2.0835)
    assert wall.result.converged and wall.result.days == 14
    mean, sd = wall.prior
    assert mean == pytest.approx(np.log(wall.result.u_value / 2.0835))
    assert sd == pytest.approx(np.sqrt(np.log1p(wall.result.rel_std**2)))

    model = build_fifth_order_model(building)
    plain = correction_groups(model)
    assert plain == ["k_env", "k_win", "k_floor"]
    model = model.__class__(**{**model.__dict__, "in_situ": in_situ_priors(measured)})
    groups = correction_groups(model)
    assert groups == ["k_env", "k_walls", "k_win", "k_floor"]
    assert group_label("k_env", model) == "ceiling under the attic + walls to unheated spaces"
    means, sds = group_priors(groups, 0.2, model)
    assert means[1] == pytest.approx(mean) and sds[1] == pytest.approx(sd)
    assert means[0] == 0.0 and sds[0] == pytest.approx(np.sqrt(np.log1p(0.04)))
    # the walls take their factor, the rest of the envelope group its own
    env = scaled_envelope(model.envelope, {"k_env": 0.9, "k_walls": 0.7})
    assert env.walls_u == pytest.approx(0.7 * model.envelope.walls_u)
    assert env.attic_u == pytest.approx(0.9 * model.envelope.attic_u)
    assert env.roof_u == pytest.approx(0.9 * model.envelope.roof_u)


def test_a_given_value_and_its_uncertainty(building, tmp_path):
    cfg = _config({"walls": {"u_value": 1.6, "rel_std": 0.1}}, tmp_path)
    wall = measure_in_situ(cfg, building)["walls"]
    assert wall.source == "given" and wall.result.u_value == 1.6
    assert wall.prior[1] == pytest.approx(np.sqrt(np.log1p(0.01)))


@pytest.mark.parametrize(
    ("entry", "message"),
    [
        ({"windows": {"u_value": 1.0, "rel_std": 0.1}}, "a heat-flux meter measures one of"),
        ({"walls": {"u_value": 1.0}}, "give its rel_std too"),
        ({"walls": {"file": "x.csv", "u_value": 1.0, "rel_std": 0.1}}, "give either file"),
        ({"walls": {"file": "x.csv", "columns": {"heat_flux": "q"}}}, "temp_in"),
        (
            {"walls": {"file": "x.csv",
                       "columns": {"heat_flux": "q", "temp_in": "T", "temp_out": "T"}}},
            "needs its own log column",
        ),
        (
            {"walls": {"file": "x.csv", "columns": {"heat_flux": "q", "temp_in": "Ti",
                                                    "temp_out": "Te", "rh": "RH"}}},
            "not used",
        ),
    ],
)
def test_configuration_errors_name_the_key(entry, message, tmp_path):
    with pytest.raises(ThermocalInputError, match=message) as err:
        _config(entry, tmp_path)
    assert "in_situ" in str(err.value)


def _log(tmp_path, rows: pd.DataFrame) -> Path:
    path = tmp_path / "plate.csv"
    rows.to_csv(path, index=False)
    return path


def test_log_errors_say_what_to_do(building, tmp_path):
    good = pd.read_csv(LOG)
    cases = [
        ({"file": str(tmp_path / "missing.csv")}, None, "not found .in_situ.walls.file"),
        ({}, good.assign(Ti=good["Ti"] + 273.15), "like Kelvin.*in_situ.walls.temperature_unit"),
        ({}, good.assign(q_W_m2=-good["q_W_m2"]), "heat_flux_sign: inward"),
        ({}, good.iloc[:48], "has not converged .duration: 2 days < 3"),
        ({"component": "north window"}, good, "is not a external_wall"),
        ({"other_side": "unheated"}, good, "the component sets"),
    ]
    for spec, rows, message in cases:
        entry = {"file": str(LOG), "columns": COLUMNS, **spec}
        if rows is not None:
            entry["file"] = str(_log(tmp_path, rows))
        cfg = _config({"walls": entry}, tmp_path)
        with pytest.raises(ThermocalInputError, match=message):
            measure_in_situ(cfg, building, 1.0)
    # an inward-positive plate, declared, reads the same wall
    cfg = _config(
        {"walls": {"file": str(_log(tmp_path, good.assign(q_W_m2=-good["q_W_m2"]))),
                   "columns": COLUMNS, "heat_flux_sign": "inward"}}, tmp_path,
    )  # fmt: skip
    assert measure_in_situ(cfg, building, 1.0)["walls"].result.u_value == pytest.approx(
        1.578, abs=1e-3
    )


def test_components_of_different_u_values_need_the_plates_component(tmp_path):
    import yaml

    data = yaml.safe_load((REF / "building.yaml").read_text())
    data["components"][0]["u_value"] = 1.2  # the north wall differs from the others
    (tmp_path / "b.yaml").write_text(yaml.safe_dump(data))
    building = read_envelope(tmp_path / "b.yaml")
    cfg = _config({"walls": {"u_value": 1.0, "rel_std": 0.1}}, tmp_path)
    with pytest.raises(ThermocalInputError, match="say which one the plate was on"):
        measure_in_situ(cfg, building)
    cfg = _config({"walls": {"u_value": 1.0, "rel_std": 0.1, "component": "north wall"}}, tmp_path)
    assert measure_in_situ(cfg, building)["walls"].described_u == 1.2


def test_the_summary_offers_the_plate_when_the_data_leave_the_envelope_to_the_prior():
    from thermocal.retrofit.correction import Correction

    def correction(separated: bool, measured=()):
        return Correction(
            factors={"k_env": 0.8, "k_win": 1.0}, names=["k_env", "k_win"],
            z_map=np.zeros(2), cov_z=np.eye(2), cov_data=np.eye(2), z_lower=-np.ones(2),
            z_upper=np.ones(2), prior_std={"k_env": 0.2, "k_win": 0.2},
            posterior_std={"k_env": 0.19, "k_win": 0.19},
            separated={"k_env": separated, "k_win": False},
        )  # fmt: skip

    assert "in_situ section" in correction(False).summary()
    assert "in_situ section" not in correction(True).summary()


def test_a_ratio_beyond_the_corrections_range_is_refused(building, tmp_path):
    cfg = _config({"walls": {"u_value": 0.5, "rel_std": 0.1}}, tmp_path)  # 0.24 x 2.08
    with pytest.raises(ThermocalInputError, match="beyond the range the data may correct"):
        measure_in_situ(cfg, building)


def test_towards_an_unheated_space_the_films_are_the_inside_ones_on_both_sides(
    building, tmp_path
):
    """A plate on the ceiling under the attic with the ceiling's two surface temperatures:
    U adds ISO 6946's upward inside resistance on both sides (0.10 + 0.10), as the model
    describes an element towards an unheated space, not an outside one (0.04)."""
    n = 24 * 4
    log = pd.DataFrame(
        {
            "time": pd.date_range("2015-02-02", periods=n, freq="1h").strftime("%Y-%m-%d %H:%M"),
            "q": np.full(n, 2.0),
            "Tsi": np.full(n, 19.0),
            "Tse": np.full(n, 9.0),
        }
    )
    cfg = _config(
        {"attic_ceiling": {"file": str(_log(tmp_path, log)), "temperatures": "surface",
                           "columns": {"heat_flux": "q", "temp_in": "Tsi", "temp_out": "Tse"}}},
        tmp_path,
    )  # fmt: skip
    ceiling = measure_in_situ(cfg, building, 1.0)["attic_ceiling"]
    assert ceiling.result.conductance == pytest.approx(0.2)
    assert ceiling.result.u_value == pytest.approx(1.0 / (0.10 + 5.0 + 0.10))
