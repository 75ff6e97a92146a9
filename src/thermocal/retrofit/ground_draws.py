"""The ground's uncertain inputs in the uncertainty draws of the retrofit analysis.

The house description gives the ground path through ISO 13370 with inputs a user rarely
knows; each draw (except the first, the estimate) takes them from distributions argued from
the standards, independently of each other:

- **soil thermal conductivity** ``lambda``: log-normal with the building file's value as
  median (ISO 13370:2017's 2.0 W/(m K) for an unknown soil, sand or gravel) and
  ``sigma_ln = ln(3.5 / 2.0) / 1.645 = 0.34``: the 95th percentile is ISO 13370 Table 7's
  homogeneous rock (3.5 W/(m K)), the 5th its mirror 1.14 W/(m K), below the clay/silt category
  (1.5) by the spread of moist fine-grained soils with density and water content (clays
  0.9-1.9 W/(m K) at 1,600-1,900 kg/m3; Farouki 1981);
- **air change of an unheated basement** ``n``: log-normal with the building file's value as
  median (ISO 13370's 0.3 1/h) and ``sigma_ln = ln(10) / (2 x 1.645) = 0.70``: 5-95 % from
  0.1 to 1 1/h, the first three classes of ISO 13789's conventional air change rates of
  unheated spaces (no openings, joints sealed: 0.1; joints sealed, no openings: 0.5; small
  ventilation openings: 1); a leaky cellar with open joints or permanent openings (3 or 10
  1/h) is a description the user should give;
- **the slab-edge junction** that under-slab insulation leaves (a slab on ground with an
  insulation measure): the change of its linear thermal transmittance,
  :data:`thermocal.retrofit.model.SLAB_EDGE_PSI_CHANGE` (0.41 W/(m K), tabulated default
  values for a soil of 2.0 W/(m K)) times the drawn soil's conductivity over 2.0 (the
  junction's heat flows through the ground) times a log-normal factor with ``sigma_ln =
  0.2``: ISO 14683's accuracy of thermal-bridge catalogues and manual calculations (+/- 20 %).

The measurements determine the total heat balance, not how it splits between the ground and
the rest: a draw whose ground path carries ``Delta Q`` more heat than the estimate's at the
calibration period's mean temperatures (indoor, outdoor, ground at the model's depth) has its
``H_est`` lowered by ``Delta Q / (Ti - Te)`` (as the internal gains' factor does), so the
ground's uncertainty reaches the demand where the year's conditions differ from the
calibration's, and the savings through the measures' share of the ground path.

References
----------
ISO 13370:2017, Table 7 (thermal properties of the ground), 9.4 (unheated basement).
ISO 13789:2007, Table 3 (conventional air change rates between unheated spaces and the
external environment).
ISO 14683:2007, 5.1, Table 1 (expected accuracy of psi values by method: catalogues and
manual calculations +/- 20 %, default values 0 to +50 %).
Arrêté du 31 mars 2021 relatif aux méthodes et procédures applicables au diagnostic de
performance énergétique, annexe 1 ("méthode 3CL-DPE 2021"), 3.4.1 (default psi values of the
floor / wall junction).
O. T. Farouki, "Thermal properties of soils", CRREL Monograph 81-1, US Army Cold Regions
Research and Engineering Laboratory, 1981.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

#: Standard deviation of ln(soil conductivity) [-]: 95th percentile at ISO 13370's rock, 3.5.
SOIL_STD_LOG = float(np.log(3.5 / 2.0) / 1.645)
#: Standard deviation of ln(basement air change) [-]: 5-95 % from 0.1 to 1 1/h (ISO 13789).
BASEMENT_ACH_STD_LOG = float(np.log(10.0) / (2.0 * 1.645))
#: Standard deviation of ln(slab-edge psi change) [-]: ISO 14683's +/- 20 % for catalogues.
SLAB_EDGE_PSI_STD_LOG = 0.2

#: What is drawn, for the report and results.json.
DESCRIPTION = {
    "soil_conductivity": "log-normal, median the building file's ground.soil_conductivity "
    f"(ISO 13370 default 2.0 W/(m K)), sd of ln {SOIL_STD_LOG:.2f}: 90 % within 1.1-3.5 "
    "W/(m K) (ISO 13370 Table 7: clay/silt 1.5, sand/gravel 2.0, rock 3.5)",
    "basement_air_change_rate": "log-normal, median the building file's "
    "ground.basement_air_change_rate (default 0.3 1/h), sd of ln "
    f"{BASEMENT_ACH_STD_LOG:.2f}: 90 % within 0.1-1 1/h (ISO 13789 conventional rates of "
    "unheated spaces)",
    "slab_edge_psi_change": "0.41 W/(m K) at soil 2.0 W/(m K) (default psi values of the "
    "wall / floor junction, French 3CL-DPE 2021 method, 3.4.1: under-slab insulation 0.80 "
    "against an uninsulated floor 0.39), "
    "proportional to the drawn soil conductivity, times a log-normal factor with sd of ln "
    f"{SLAB_EDGE_PSI_STD_LOG:.2f} (ISO 14683: +/- 20 %)",
}


def draw_ground_inputs(
    building, model, n: int, seed: int = 0, *, soil: bool = True
) -> dict[str, np.ndarray]:
    """Soil conductivity, basement air change and slab-edge psi change of ``n`` draws.

    Parameters
    ----------
    building : thermocal.io.envelope.EnvelopeDescription
    model : FifthOrderModel
    n : int
        Number of draws, the first being the estimate (the building file's values).
    seed : int
    soil : bool
        Draw the soil conductivity (default). ``False`` when the data's correction of a floor on
        the ground carries it (``k_floor`` scales the ground path, its prior includes the
        soil's, :func:`thermocal.retrofit.correction.group_prior_std_log`): the soil stays the
        building file's in every draw, the edge keeps its own spread.

    Returns
    -------
    dict with ``soil_conductivity`` [W/(m K)], ``basement_air_change_rate`` [1/h] and
    ``slab_edge_psi_change`` [W/(m K)], arrays of shape (n,); only the inputs the house has
    (a basement's air change for an unheated basement, the edge for a slab).
    """
    rng = np.random.default_rng(seed + 15485863)
    g = building.ground
    z = rng.standard_normal((n, 3))
    z[0] = 0.0
    soil_std = SOIL_STD_LOG if soil else 0.0
    out = {"soil_conductivity": float(g.soil_conductivity) * np.exp(soil_std * z[:, 0])}
    if model.ground.kind == "unheated_basement":
        out["basement_air_change_rate"] = float(g.basement_air_change_rate) * np.exp(
            BASEMENT_ACH_STD_LOG * z[:, 1]
        )
    if model.envelope.floor_edge_psi > 0:
        # the junction's heat flows through the ground: it scales with the drawn soil
        out["slab_edge_psi_change"] = (
            model.envelope.floor_edge_psi
            * out["soil_conductivity"] / float(g.soil_conductivity)
            * np.exp(SLAB_EDGE_PSI_STD_LOG * z[:, 2])
        )  # fmt: skip
    return out


def ground_overrides(building, model, inputs: dict[str, np.ndarray]) -> list[dict]:
    """Per draw, the envelope fields that carry the drawn ground (``ground``,
    ``floor_edge_psi``) for :func:`dataclasses.replace`; the first draw: none."""
    from thermocal.retrofit.model import ground_path

    n = len(inputs["soil_conductivity"])
    out: list[dict] = [{}]
    for d in range(1, n):
        ach = inputs.get("basement_air_change_rate")
        fields = {
            "ground": ground_path(
                building,
                model.envelope,
                soil_conductivity=float(inputs["soil_conductivity"][d]),
                basement_air_changes=None if ach is None else float(ach[d]),
            )
        }
        if "slab_edge_psi_change" in inputs:
            fields["floor_edge_psi"] = float(inputs["slab_edge_psi_change"][d])
        out.append(fields)
    return out


def ground_flow(h: dict, ti: float, te: float, tgr: float) -> float:
    """Steady heat flow [W] from the indoor air through the floor element (cellar ceiling or
    slab) at constant indoor, outdoor and ground temperatures [C].

    Parameters
    ----------
    h : dict
        Conductances [W/K] of :meth:`FifthOrderModel.conductances` (``H_gf_in``, ``H_gf_gr``,
        ``H_gf_e``; with the split inside its pairs too: the floor's steady flow to the ground
        and outdoor air in the whole network).
    """
    h_in, h_gr, h_e = float(h["H_gf_in"]), float(h["H_gf_gr"]), float(h["H_gf_e"])
    if h.get("interior_split"):
        # the split inside: the floor node's steady temperature in the whole network
        from thermocal.retrofit.interior import steady_temperatures

        t_gf = steady_temperatures(h, ti, te, tgr)["Tgf"]
        return h_gr * (t_gf - tgr) + h_e * (t_gf - te)
    t_gf = (h_in * ti + h_gr * tgr + h_e * te) / (h_in + h_gr + h_e)
    return h_in * (ti - t_gf)


def h_est_shifts(model, envelopes, overrides: list[dict], means: dict) -> np.ndarray:
    """Shift of each draw's ``H_est`` [W/K] that keeps the calibration period's heat balance
    when the drawn ground path carries more or less heat than the estimate's.

    Parameters
    ----------
    model : FifthOrderModel
    envelopes : list of EnvelopeComponents
        Each draw's envelope before its ground override (no measures).
    overrides : list of dict, from :func:`ground_overrides`
    means : dict
        Calibration-period means ``Ti``, ``Te``, ``Tgr`` [C].

    Returns
    -------
    ndarray (n,) [W/K], 0 for the first draw.
    """
    ti, te, tgr = float(means["Ti"]), float(means["Te"]), float(means["Tgr"])
    out = np.zeros(len(envelopes))
    if ti - te < 1.0:
        return out
    for d, (env, fields) in enumerate(zip(envelopes, overrides, strict=True)):
        if "ground" not in fields:
            continue
        q0 = ground_flow(model.conductances(env), ti, te, tgr)
        q1 = ground_flow(model.conductances(replace(env, ground=fields["ground"])), ti, te, tgr)
        out[d] = -(q1 - q0) / (ti - te)
    return out
