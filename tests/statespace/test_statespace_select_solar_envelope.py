"""The sun on the envelope: ASHRAE 140 Case 900 (heavy) held at 20 C by a thermostat in a Denver
January, simulated by EnergyPlus 25.2 (``tests/reference/fit_case900_thermostat``: its
make_reference.py and truth.json, the heat loss coefficient from steady EnergyPlus runs:
87.4 W/K).

The family's models let the sun into the interior only. The heavy walls absorb much of it, and
the only way the interior-only models can match the data is a smaller heat loss coefficient.
``thermocal select`` ended at TiTe: 52.8 W/K [48.0, 58.5], no flag; ``fit --strict`` exited 0
(exploratory test, 2026-12-01). With the envelope's aperture ``Ae`` among the extensions the
selection takes it, and the interval covers the truth."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
import pytest

from thermocal.statespace.families import BACHER_MADSEN_EXTENSIONS, bacher_madsen_family

REFERENCE = Path(__file__).resolve().parents[1] / "reference" / "fit_case900_thermostat"


def _data() -> pd.DataFrame:
    data = pd.read_csv(REFERENCE / "case900_thermostat_january_1h.csv.gz")
    data["t"] = pd.to_datetime(data[data.columns[0]])
    return data


def test_the_envelope_aperture_is_an_extension_of_every_member_with_an_envelope():
    models, extensions, _ = bacher_madsen_family()
    for name in ("TiTe", "TiTeTh", "TiTeThRia", "TiTmTeTh", "TiTmTeThRia"):
        with_sun = name.replace("Ria", "") + "Ae" + ("Ria" if "Ria" in name else "")
        assert with_sun in extensions[name], name
    assert "Ae" in models["TiTeAe"].parameters
    assert extensions == {k: v for k, v in BACHER_MADSEN_EXTENSIONS.items()}
    no_sun, no_sun_extensions, _ = bacher_madsen_family(solar_unit=None)
    assert not any("Ae" in n for n in no_sun)
    assert not any("Ae" in e for v in no_sun_extensions.values() for e in v)


@pytest.mark.slow
def test_the_sun_on_a_heavy_envelope_is_found_and_the_heat_loss_coefficient_covered():
    truth = json.loads((REFERENCE / "truth.json").read_text())["H_outdoor_dQ_dTa"]
    models, _, _ = bacher_madsen_family()  # Ph in kW, Ps in kW/m2, as the fixture
    data = _data()
    fits = {}
    for name in ("TiTe", "TiTeAe"):
        fits[name] = models[name].fit(data, time_column="t", n_starts=2)
    gain = fits["TiTeAe"].loglike - fits["TiTe"].loglike
    assert gain > 50.0, gain  # measured: +104 log-units for one parameter
    interior_only = fits["TiTe"].heat_loss_coefficient()
    both = fits["TiTeAe"].heat_loss_coefficient()
    assert interior_only["upper"] < truth  # the bias the selection used to end with
    assert both["lower"] < truth < both["upper"], (both, truth)
