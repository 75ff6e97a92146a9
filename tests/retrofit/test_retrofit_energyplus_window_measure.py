"""Why the retrofit under-estimates the windows measure on the EnergyPlus twin of NREL's
SingleFamilyHouse: its U part and its g part (docs/retrofit-twins.md, "The windows measure: U
part and g part").

``tests/reference/retrofit_energyplus_house/diagnose_window_measure.py`` ran EnergyPlus 25.2
(the reference house's year with the old glazing, U 0.76 with the old g, the old U with g
0.50, and the whole measure) and thermocal's retrofit on the twin with the plate and the
measured air change (the whole measure, its U alone, its g alone) into ``window_measure.json``.
Here thermocal's part is run again (one analysis of the twin, a few seconds) and compared with
the committed EnergyPlus part: the U part agrees within 3 pp, the g part's penalty is larger in
thermocal, because thermocal turns more of the sun the new glass cuts into heating (its window
sun goes into the air and internal-mass nodes, where EnergyPlus's is absorbed by the surfaces
of a poorly insulated envelope and partly conducted out).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from conftest import load_script, shared_data_path

REF = Path(__file__).resolve().parents[1] / "reference" / "retrofit_energyplus_house"
PARTS = ("u_only", "g_on_new_glass", "whole", "g_only_on_old_glass")


@pytest.fixture(scope="module")
def study() -> dict:
    return json.loads((REF / "window_measure.json").read_text())


@pytest.fixture(scope="module")
def thermocal_now() -> dict:
    """thermocal's part of the study, run now (the script's own function)."""
    weather = shared_data_path("weather_switzerland", "Zuerich-SMA_2015.epw")
    script = load_script(REF / "diagnose_window_measure.py", "diagnose_window_measure_house")
    return script.thermocal(weather)


@pytest.mark.slow
def test_window_measure_record_is_this_run(study, thermocal_now):
    """The committed thermocal numbers are what thermocal computes now (a change that moves
    them fails here: rerun ``diagnose_window_measure.py WEATHER --no-energyplus``), and the
    EnergyPlus runs are the reference's (the old glazing and the whole measure as in
    ``reference.json``)."""
    rec = study["thermocal"]
    for part in PARTS:
        assert thermocal_now["saving_pct"][part] == pytest.approx(
            rec["saving_pct"][part], abs=0.1
        ), part
    for glass in ("new_glass", "old_glass"):
        now = thermocal_now["sun_cut_oct_apr"][glass]
        was = rec["sun_cut_oct_apr"][glass]
        assert now["utilisation"] == pytest.approx(was["utilisation"], abs=0.01), glass
    assert thermocal_now["window_factor_k_win"] == pytest.approx(
        rec["window_factor_k_win"], abs=0.01
    )
    ref = json.loads((REF / "reference.json").read_text())["annual_heating_kWh"]
    ep = study["energyplus"]["annual_heating_kWh"]
    assert ep["old"] == pytest.approx(ref["none"], rel=1e-6)
    assert ep["whole"] == pytest.approx(ref["windows"], rel=1e-6)


@pytest.mark.slow
def test_window_measure_u_part_agrees_g_part_does_not(study, thermocal_now):
    """Measured 2026-11-30 (thermocal / EnergyPlus): U part 27.7 / 28.6 %, g part on the new
    glass -12.0 / -7.8 %, whole 15.6 / 20.8 %; the g part on the old glass -14.0 / -8.8 %. The
    U part is within 3 pp; the g part's penalty is more than 3 pp larger in thermocal and makes
    most of the whole measure's under-estimate (4.2 of 5.2 pp)."""
    tc, ep = thermocal_now["saving_pct"], study["energyplus"]["saving_pct"]
    assert abs(tc["u_only"] - ep["u_only"]) < 3.0, (tc, ep)  # (-0.9 pp)
    assert tc["g_on_new_glass"] < ep["g_on_new_glass"] - 3.0, (tc, ep)  # (-4.2 pp)
    assert tc["g_only_on_old_glass"] < ep["g_only_on_old_glass"] - 3.0, (tc, ep)  # (-5.2 pp)
    whole_gap = ep["whole"] - tc["whole"]  # (5.2 pp)
    g_gap = ep["g_on_new_glass"] - tc["g_on_new_glass"]
    assert whole_gap > 3.0 and g_gap > abs(ep["u_only"] - tc["u_only"])
    assert g_gap > 0.6 * whole_gap, (g_gap, whole_gap)  # (0.81)


@pytest.mark.slow
def test_window_sun_turns_into_heating_more_in_thermocal(study, thermocal_now):
    """October - April the new g cuts the transmitted sun by 2,148 kWh in thermocal and raises
    its heating by 1,216 kWh (57 %; on the old glass 1,326 kWh, 62 %); in EnergyPlus by 2,219
    and 758 kWh (34 %; old glass 2,366 and 821 kWh, 35 %): the rest of EnergyPlus's sun,
    absorbed by the room's surfaces, had left through the walls (27 %), the slab (18 %), back
    out through the windows (12 %) and the ceiling (5 %); thermocal's heat balance loses 43 %
    of its cut (envelope 27 %, floor 9 %, air change 4 %, windows 3 %)."""
    for glass in ("new_glass", "old_glass"):
        tc = thermocal_now["sun_cut_oct_apr"][glass]
        ep = study["energyplus"]["sun_cut_oct_apr"][glass]
        # (about the same sun cut: 2,148 vs 2,219 kWh on the new glass)
        assert tc["transmitted_sun_cut_kWh"] == pytest.approx(
            ep["transmitted_sun_cut_kWh"], rel=0.15
        )
        assert tc["utilisation"] > ep["utilisation"] + 0.15, (glass, tc, ep)  # (0.57 vs 0.34)
        assert ep["utilisation"] < 0.4
        shares = ep["loss_fall_share_of_the_cut"]
        envelope = sum(shares[k] for k in ("walls", "wall_to_the_garage", "floor", "ceiling"))
        assert envelope + shares["windows"] > 0.5, shares  # (0.62 on the new glass)
        assert abs(shares["rest"]) < 0.05, shares  # EnergyPlus's balance closes
        # the floor and the windows: where thermocal loses least of what EnergyPlus loses
        tc_shares = tc["loss_fall_share_of_the_cut"]
        assert tc_shares["floor"] + tc_shares["windows"] < shares["floor"] + shares["windows"]


@pytest.mark.slow
def test_window_conductance_with_films(study, thermocal_now):
    """EnergyPlus's old windows conduct 2.35 (February 2 - March 15) - 2.41 (October - April)
    W/(m2 K) with their films, 0.73-0.75 of the described 3.23; the calibration's window factor
    (0.797, posterior sd of its log 0.16) is within one sd of it. The new glazing conducts
    0.69-0.70 in EnergyPlus, 0.72 in thermocal (the old windows' films correction kept)."""
    g = study["energyplus"]["window_conductance_W_per_m2K"]
    k_win = thermocal_now["window_factor_k_win"]
    sd = thermocal_now["k_win_posterior_std_log"]
    for period in ("feb2_mar15", "oct_apr"):
        k_ep = g["old"][period]["regression"] / g["described"]["old"]
        assert 0.70 < k_ep < 0.78, (period, k_ep)
        assert abs(math.log(k_win / k_ep)) < sd, (period, k_win, k_ep, sd)
        assert g["new"][period]["regression"] < g["described"]["new"]
    new_tc = thermocal_now["window_u_W_per_m2K"]["new"]
    assert new_tc == pytest.approx(g["new"]["oct_apr"]["regression"], abs=0.05)
