"""The radiant share of the gains an IDF declares, step by step (the form of the identified heat
that follows the composition of the gains)."""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd
import pytest
from test_multizone_idf import _box

from thermocal.multizone.idf import IdfImportWarning, read_idf
from thermocal.multizone.idf.loads import declared_radiant_fraction, people_sensible_heat

GAINS = """
People,P,Z1,Occ,People,4,,,0.3,,Act;
Schedule:Constant,Act,,120;
Lights,L,Z1,Always,LightingLevel,200,,,0,0.7,0.2,1;
ElectricEquipment,E,Z1,Occ,EquipmentLevel,300,,,0.1,0.5,0;
Schedule:Constant,Always,,1;
Schedule:Compact,Occ,Fraction,Through: 12/31,For: AllDays,Until: 08:00,0,Until: 18:00,1,
  Until: 24:00,0;
"""


def test_declared_fraction_follows_the_composition_hour_by_hour(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IdfImportWarning)
        building = read_idf(_box(tmp_path, extra=GAINS))
    times = pd.date_range("2001-01-08", periods=48, freq="1h")
    got = declared_radiant_fraction(building.idf_info, ["Z1"], times, "1h", fallback=0.6)
    people = 4 * float(people_sensible_heat(120.0))  # sensible at 22 C [W]
    equipment = 300 * (1 - 0.1)  # the latent tenth removed; radiant 0.5 of the whole level
    occupied = (people * 0.3 + 200 * 0.9 + 300 * 0.5) / (people + 200 + equipment)
    hour = times.hour
    expected = np.where((hour >= 8) & (hour < 18), occupied, 0.9)  # lights alone: 0.7 + 0.2
    np.testing.assert_allclose(got[:, 0], expected, rtol=1e-9)


def test_zone_without_gains_takes_the_fallback(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IdfImportWarning)
        building = read_idf(_box(tmp_path))
    times = pd.date_range("2001-01-08", periods=5, freq="1h")
    got = declared_radiant_fraction(building.idf_info, ["Z1"], times, "1h", fallback=0.6)
    assert got == pytest.approx(np.full((5, 1), 0.6))
