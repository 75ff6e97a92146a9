"""Model inputs of the fifth-order model from weather and the building file.

- solar gains through the windows ``phi_sol`` [W]:
  :func:`thermocal.physics.solar.window_solar_gains` (ISO 52016-1 6.5.13.2: aperture x g-value
  x shading x ``F_w = 0.9`` for non-normal incidence x irradiance on the window plane);
- solar radiation absorbed on the outer surfaces of roof and walls minus their long-wave loss
  to the sky, ``phi_abs_roof``, ``phi_abs_walls`` [W] (ISO 52016-1 6.5.13.3; ISO 13790 11.3.5:
  ``F_r h_r Delta theta_er`` with the sky view factor ``F_r = (1 + cos tilt) / 2``,
  ``h_r = 4.14 W/(m2 K)`` and ``Delta theta_er = 11 K``). This is deliberately NOT
  :func:`thermocal.physics.solar.opaque_solar_gains`: ISO 13790 multiplies the absorbed
  radiation by ``R_se U`` because its heat-balance model has no envelope node, so only the
  share that reaches the inside counts. The RC model instead puts the absorbed radiation on
  the outer surface of its ``Tenv`` node and lets the network decide how much flows inward
  (:func:`thermocal.retrofit.model.element_conductances` gives the share
  ``2 Hc / (A/Rse + 2 Hc)`` entering the node); applying ``R_se U`` here as well would count
  the outer surface resistance twice.

The heating power ``phi_h`` comes from :func:`thermocal.physics.hydronics.heating_power` and the
ground temperature ``Tgr`` from :func:`thermocal.physics.ground.ground_temperature` (called
directly by :mod:`thermocal.retrofit.data` and :mod:`thermocal.retrofit.workflow`).

Irradiance columns are interval means labelled by the interval start (thermocal convention),
so sun positions are taken at the interval midpoints.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

#: ISO 52016-1 default correction of the g-value for non-normal incidence [-].
WINDOW_INCIDENCE_FACTOR = 0.9
#: ISO 13790 11.3.5 / ISO 52016-1: external radiative coefficient [W/(m2 K)] and mean
#: difference between air and apparent sky temperature [K].
H_RE_SKY = 4.14
DELTA_THETA_ER = 11.0


def solar_inputs(frame: pd.DataFrame, building) -> pd.DataFrame:
    """Window gains and absorbed outer-surface radiation of roof and walls [W].

    The window gains are :func:`thermocal.physics.solar.window_solar_gains` with
    ``g_correction = 0.9``. The absorbed radiation ``A (alpha I_sol - F_r h_r dT_er)`` is the
    full net radiation on the outer surface, without the ``R_se U`` factor of ISO 13790
    11.3.4 (:func:`thermocal.physics.solar.opaque_solar_gains`): the RC model places it on the
    envelope node through the outer half of the element (module docstring), which already
    accounts for the fraction re-emitted at the outer surface.

    Parameters
    ----------
    frame : pd.DataFrame
        Regular DatetimeIndex (interval starts) with ``dni`` and ``dhi`` [W/m2] (``ghi`` is
        computed as ``dhi + dni cos(zenith)`` when absent).
    building : thermocal.io.envelope.EnvelopeDescription
        Validated building: tilt and azimuth are set for every component, g_value,
        frame_fraction and shading_factor for windows, absorptance for opaque components
        (defaults applied by :mod:`thermocal.io.envelope`).

    Returns
    -------
    pd.DataFrame with columns ``phi_sol``, ``phi_abs_roof``, ``phi_abs_walls`` [W].
    """
    from thermocal.physics.solar import irradiance_on_surfaces, window_solar_gains

    loc = building.location
    data = frame[["dni", "dhi"] + (["ghi"] if "ghi" in frame else [])]
    orientations = {}
    for c in building.components:
        if c.type in ("window", "roof", "external_wall"):
            orientations[c.name] = (float(c.tilt), float(c.azimuth))
    poa_frames = irradiance_on_surfaces(
        data, loc.latitude, loc.longitude, orientations, altitude=loc.altitude
    )

    def poa(name):
        return np.nan_to_num(poa_frames[name]["poa_global"].to_numpy(float), nan=0.0).clip(0.0)

    n = len(frame)
    phi_sol = np.zeros(n)
    absorbed = {"roof": np.zeros(n), "external_wall": np.zeros(n)}
    for c in building.components:
        if c.type == "window":
            irradiance = pd.DataFrame({"poa_global": poa(c.name)}, index=frame.index)
            phi_sol += window_solar_gains(
                irradiance,
                float(c.area),
                float(c.g_value),
                frame_fraction=float(c.frame_fraction),
                shading_factor=float(c.shading_factor),
                g_correction=WINDOW_INCIDENCE_FACTOR,
            ).to_numpy()
        elif c.type in absorbed:
            # net radiation on the outer surface, NOT times R_se U as in ISO 13790 11.3.4
            # (opaque_solar_gains): the RC model's outer half-element takes that role
            alpha = float(c.absorptance)
            sky_view = 0.5 * (1.0 + np.cos(np.radians(float(c.tilt))))
            absorbed[c.type] += c.area * (
                alpha * poa(c.name) - sky_view * H_RE_SKY * DELTA_THETA_ER
            )
    return pd.DataFrame(
        {
            "phi_sol": phi_sol,
            "phi_abs_roof": absorbed["roof"],
            "phi_abs_walls": absorbed["external_wall"],
        },
        index=frame.index,
    )
