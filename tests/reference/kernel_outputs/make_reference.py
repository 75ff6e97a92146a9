"""Outputs of the multi-zone time loop on a small building, stored as the reference that any
speed-up of the compiled kernel (``thermocal.multizone._kernel``) must reproduce (issue 22).

Generated with the kernel of commit de53112 (before the speed-ups) and regenerated on
2026-11-30 when the room side of windows took ISO 15099's natural convection and the glass
its resistance from EnergyPlus' film correlations, and on 2026-12-01 when the windows' ISO
15099 coefficient was no longer clipped at twice its matrix part (at most 1.2e-5 K, 0.3 W)
(physics, not speed), by
``python tests/reference/kernel_outputs/make_reference.py``; the test
``tests/multizone/test_multizone_kernel_reference.py`` recomputes the same cases with the
current code. The building is the generated single-family house (9 zones, TARP interior
convection, exact interior and exterior long-wave exchange, wind-dependent exterior
convection), synthetic January weather, 15-minute steps, 2 warm-up days and 3 days:

- ``free``: free floating with 150 W given heat per zone;
- ``ideal``: ideal heating (14 C) and cooling (15.5 C) in the heated zones (both happen);
- ``inverse``: exact inverse on the air temperatures of the free run + 1 K (one substitution
  with the air temperatures prescribed);
- ``operative``: exact inverse on the operative temperature with half of the heat radiant
  (the general inverse, two substitutions per step);
- ``pid``: discrete PID per zone on the same reference.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

HERE = Path(__file__).resolve().parent
FILE = HERE / "kernel_outputs.npz"


def weather() -> tuple[pd.DataFrame, dict]:
    """Synthetic January days: daily swing of the outdoor air and the sun, some wind."""
    times = pd.date_range("2023-01-01", periods=24 * 8, freq="1h", tz="UTC")
    hours = np.arange(len(times))
    sun = np.clip(np.sin(2 * np.pi * (hours - 6) / 24), 0, None)
    frame = pd.DataFrame(
        {
            "temp_air": 2.0 + 6.0 * np.sin(2 * np.pi * (hours - 9) / 24),
            "ghi": 400 * sun,
            "dni": 500 * sun,
            "dhi": 100 * sun,
            "wind_speed": 3.0 + 2.0 * np.cos(2 * np.pi * hours / 37),
            "relative_humidity": 70.0,
            "pressure": 101325.0,
        },
        index=times,
    )
    return frame, {"latitude": 48.0, "longitude": 11.0, "altitude": 500.0}


def kernel_outputs() -> dict[str, np.ndarray]:
    """The five cases' outputs with the installed thermocal."""
    from thermocal.demos.buildings import single_family_house
    from thermocal.multizone.simulation import Simulation

    frame, meta = weather()
    building = single_family_house(heating_setpoint=14.0, internal_gains_per_area=4.0)
    building = building.__class__(
        **{
            **building.__dict__,
            "zones": {
                n: z.__class__(
                    **{**z.__dict__, "cooling_setpoint": 15.5 if z.conditioned else None}
                )
                for n, z in building.zones.items()
            },
        }
    )

    def simulation():
        return Simulation(
            building,
            frame,
            meta,
            step="15min",
            start="2023-01-03",
            end="2023-01-06",
            warmup_days=2,
        )

    sim = simulation()
    nz = len(building.zones)
    out = {}
    free = sim.run(free_float=True, heat_input=np.full((len(sim.times), nz), 150.0))
    out["free/air"] = free.air_temperature.to_numpy()
    out["free/mrt"] = free.mean_radiant_temperature.to_numpy()
    ideal = simulation().run()
    out["ideal/air"] = ideal.air_temperature.to_numpy()
    out["ideal/heating"] = ideal.heating.to_numpy()
    out["ideal/cooling"] = ideal.cooling.to_numpy()
    reference = out["free/air"] + 1.0
    for name, kwargs in (
        ("inverse", {"method": "inverse"}),
        ("operative", {"method": "inverse", "feedback": "operative", "radiant_fraction": 0.5}),
        (
            "pid",
            {
                "method": "pid",
                "pid": (np.full(nz, 60.0), np.full(nz, 3.0), np.zeros(nz)),
            },
        ),
    ):
        result = simulation().track(reference, **kwargs)
        out[f"{name}/heat"] = result.heat.to_numpy()
        out[f"{name}/air"] = result.air_temperature.to_numpy()
    for key, value in out.items():
        if not np.isfinite(value).all():
            raise RuntimeError(f"{key}: not finite (the case diverges)")
    return out


if __name__ == "__main__":
    np.savez_compressed(FILE, **kernel_outputs())
    print(f"wrote {FILE}")
