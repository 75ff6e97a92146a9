"""What a run returns: the heat per zone, the result object and the list of the model's
approximations.

A part of :class:`thermocal.multizone.simulation.Simulation`, which inherits it; the methods
work on the simulation's state.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.multizone.network import (
    IN_TEMP_OUT,
)
from thermocal.multizone.results import (
    SimulationResult,
)


class Outputs:
    """What a run returns (part of :class:`~thermocal.multizone.simulation.Simulation`)."""

    def _heat_array(self, heat_input, n_steps: int, nz: int) -> np.ndarray:
        if heat_input is None:
            return np.zeros((n_steps, nz))
        if isinstance(heat_input, pd.DataFrame):
            unknown = [c for c in heat_input.columns if c not in self.building.zones]
            if unknown:
                raise ThermocalInputError(
                    f"heat_input: columns {unknown} are not zones of building "
                    f"'{self.building.name}'"
                )
            frame = heat_input.reindex(columns=list(self.building.zones), fill_value=0.0)
            if len(frame) != n_steps:
                raise ThermocalInputError(
                    f"heat_input has {len(frame)} rows but the period has {n_steps} steps"
                )
            values = frame.to_numpy(dtype=float)
        else:
            values = np.asarray(heat_input, dtype=float)
            if values.shape != (n_steps, nz):
                raise ThermocalInputError(
                    f"heat_input must have shape (n_steps, n_zones) = ({n_steps}, {nz}), got "
                    f"{values.shape}"
                )
        if not np.isfinite(values).all():
            raise ThermocalInputError("heat_input contains NaN or infinite values")
        return values

    def _result(self, air, mrt, heating, cooling, heat, faces) -> SimulationResult:
        net = self.network
        index = self.times
        zones = net.zone_names

        def frame(values, own=True):
            # the run's own arrays become the frames' blocks (no copy: a month of a 186-zone
            # building is 13 MB per quantity); the caller's heat is copied
            return pd.DataFrame(values, index=index, columns=zones, copy=not own)

        transmitted = np.asarray(net.zone_transmitted @ self._inputs.T).T
        t_out = self._inputs[:, IN_TEMP_OUT]
        conductance = net.zone_infiltration[None, :] + self._inf_dh.full()
        if len(self._inf_dt):
            conductance = conductance + self._inf_dt * np.abs(t_out[:, None] - air)
        zone, g, gdt, _, _, _, _, opened = self._vent
        if len(zone):
            # indoor-limited ventilation as the time loop switched it
            extra = opened * g
            if len(gdt):
                extra = extra + opened * gdt * np.abs(t_out[:, None] - air[:, zone])
            conductance = conductance.copy()
            np.add.at(conductance.T, zone, extra.T)
        infiltration = conductance * (t_out[:, None] - air)
        return SimulationResult(
            air_temperature=frame(air),
            operative_temperature=frame(0.5 * (air + mrt)),
            mean_radiant_temperature=frame(mrt),
            heating=frame(heating),
            cooling=frame(cooling),
            heat_input=frame(heat, own=False),
            transmitted_solar=frame(transmitted),
            infiltration=frame(infiltration),
            surface_temperature=None
            if faces is None
            else pd.DataFrame(faces, index=index, columns=net.face_names, copy=False),
            step=self.step_size,
            approximations=self.approximations(),
            zone_multipliers={
                z: m
                for z, m in getattr(self._idf_info, "zone_multipliers", {}).items()
                if m != 1.0 and z in zones
            },
        )

    def approximations(self) -> list[str]:
        """What the IDF import (and this run) flattened, skipped or replaced, one line each."""
        info = self._idf_info
        if info is None:
            return []
        out = []
        if info.unsupported:
            out.append(
                "objects not represented (skipped): "
                + ", ".join(f"{cls} ({n})" for cls, n in info.unsupported.items())
            )
        if self._scheduled is not None:
            out.append(
                "schedules applied step by step (set points, internal gains, infiltration); "
                "People sensible heat at the previous step's zone air temperature, clipped to "
                "[0, activity] as EnergyPlus, all of its change with temperature to the zone air"
            )
            out.extend(
                note
                for note in info.notes
                if "schedules='constant'" not in note and "varies" not in note
            )
        else:
            out.extend(info.notes)
        out.extend(self._convection_notes)
        if self.weather_interpolation == "energyplus":
            out.append(
                "hourly weather interpolated as EnergyPlus (irradiance between hourly values "
                "placed at the half hours); each step forced by the mean of its start and end "
                "values (EnergyPlus takes the end values)"
            )
        else:
            out.append("weather held over each hour (weather_interpolation='hold')")
        wet = int(np.count_nonzero(self._rain_flags))
        if wet:
            out.append(
                f"rain on {wet} of {len(self.times)} steps (the weather's liquid precipitation, "
                "at least 0.8 mm/h, and present weather, as EnergyPlus): wind-exposed outside "
                "faces at 1000 W/(m2 K) to the outdoor wet bulb"
                + (
                    " (the weather has no humidity: taken at the dry bulb)"
                    if self._rain_source == "weather, no humidity"
                    else ""
                )
            )
        elif not self.rain and getattr(info, "use_weather_rain", True) is False:
            out.append("rain indicators off (RunPeriod 'Use Weather File Rain Indicators' No)")
        elif self.rain and self._rain_source == "none":
            out.append(
                "rain indicators on (RunPeriod), but the weather has neither precipitation nor "
                "present weather: run dry"
            )
        shaders = getattr(info, "shading_surfaces", None)
        if shaders:
            if self._shadows is not None:
                out.append(
                    f"{len(shaders)} shading surfaces cast shadows on {len(self._shadows['beam'])} "
                    "windows and surfaces (beam by the sampled sunlit fraction, "
                    + (
                        f"updated every {info.shadow_update_days} days as EnergyPlus' "
                        "ShadowCalculation; "
                        if info.shadow_update_days
                        else "every step; "
                    )
                    + "sky diffuse as EnergyPlus: its circumsolar part like the beam, the dome "
                    "and the horizon band by their unshaded views; ground-reflected not shaded)"
                    + (
                        ", the building's own surfaces among them"
                        if any("(building surface)" in str(s.name) for s in shaders)
                        else "; the building's own surfaces cast no shadows"
                    )
                )
            elif not self.shading:
                out.append(f"{len(shaders)} shading surfaces ignored (shading=False)")
        return out
