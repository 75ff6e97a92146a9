"""Envelope descriptions (the retrofit analysis' building file): components, site, ground, emitter.

A building file (YAML or TOML) describes what an energy audit knows about a building: where it
is, its heated floor area and volume, the envelope components (roof, external walls, windows,
doors, cellar ceiling, ground floor) with area, U-value, orientation and tilt, the window g-value
and frame fraction, the heat emitter and a thermal-bridge allowance. It is validated by pydantic v2
against plausibility ranges per component type; every error names the field, the value, the
allowed range with its unit and, where the value looks like a slip of the decimal point or a
percentage, the value probably meant (a wall U-value of 19 W/(m2 K) is a typo for 0.19).

Conventions (as everywhere in thermocal): azimuth in degrees clockwise from north (0 N, 90 E, 180 S,
270 W); tilt 0 = horizontal facing up, 90 = vertical, 180 = horizontal facing down; SI units.

Example
-------
>>> from thermocal.io.envelope import read_envelope
>>> building = read_envelope("examples/buildings/single_family_house_1953.yaml")  # doctest: +SKIP
>>> building.transmission_heat_transfer_coefficient  # doctest: +SKIP
457.25

References
----------
.. [1] ISO 13789:2017, Thermal performance of buildings -- Transmission and ventilation heat
   transfer coefficients -- Calculation method, clause 6 (H_T = sum A U + thermal bridges).
.. [2] ISO 13370:2017, Thermal performance of buildings -- Heat transfer via the ground.
.. [3] SIA 380/1:2016, Thermische Energie im Hochbau (Swiss plausibility of U-values and the
   thermal-bridge allowance).
"""

from __future__ import annotations

import difflib
import math
import re
import tomllib
from collections.abc import Mapping
from functools import cached_property
from pathlib import Path
from typing import Any, Literal
from zoneinfo import ZoneInfo, ZoneInfoNotFoundError

import yaml
from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    ValidationError,
    field_validator,
    model_validator,
)
from pydantic_core import PydanticCustomError

from thermocal.errors import ThermocalInputError

__all__ = [
    "COMPONENT_TYPES",
    "OPAQUE_TYPES",
    "PLAUSIBLE_RANGES",
    "EnvelopeDescription",
    "Component",
    "Ground",
    "Site",
    "envelope_from_dict",
    "is_envelope_tree",
    "is_multizone_tree",
    "read_envelope",
    "write_envelope",
]

ComponentType = Literal[
    "roof", "external_wall", "window", "cellar_ceiling", "ground_floor", "door",
    "attic_ceiling", "wall_to_unheated",
]  # fmt: skip
EmitterType = Literal["radiators", "floor_heating", "convectors"]
BasementType = Literal["unheated", "heated", "none"]

#: Envelope component types, in the order used for reports.
COMPONENT_TYPES: tuple[str, ...] = (
    "roof",
    "external_wall",
    "window",
    "door",
    "cellar_ceiling",
    "ground_floor",
    "attic_ceiling",
    "wall_to_unheated",
)
#: Component types that are opaque (absorptance applies; g-value and frame fraction do not).
OPAQUE_TYPES: frozenset[str] = frozenset(COMPONENT_TYPES) - {"window"}
#: Component types in contact with the ground or an unheated basement (no solar exposure).
GROUND_TYPES: frozenset[str] = frozenset({"cellar_ceiling", "ground_floor"})
#: Component types towards an unheated adjacent space (no solar exposure; their heat flow is
#: reduced by the temperature adjustment factor b of ISO 13789).
UNHEATED_SPACE_TYPES: frozenset[str] = frozenset({"attic_ceiling", "wall_to_unheated"})
#: Default temperature adjustment factors b [-] (ISO 13789:2017, 6.4.3: b = H_ue / (H_iu +
#: H_ue); tabulated defaults of DIN V 4108-6:2003 Table 3: ceiling under an unheated attic
#: 0.8, walls and ceilings to unheated spaces such as a garage or staircase 0.5). Give
#: ``b_factor`` on the component when the space is known better.
DEFAULT_B_FACTOR: dict[str, float] = {"attic_ceiling": 0.8, "wall_to_unheated": 0.5}

#: Default tilt per component type [deg] (0 facing up, 90 vertical, 180 facing down).
DEFAULT_TILT: dict[str, float] = {
    "roof": 35.0,
    "external_wall": 90.0,
    "window": 90.0,
    "door": 90.0,
    "cellar_ceiling": 180.0,
    "ground_floor": 180.0,
    "attic_ceiling": 0.0,
    "wall_to_unheated": 90.0,
}

#: Component types that are walls, and the tilts a wall can have [deg] (a mansard's lower
#: slope stands at about 60-75 deg; flatter is a roof).
WALL_TYPES = frozenset({"external_wall", "wall_to_unheated"})  # a door may be a roof hatch
WALL_TILT = (45.0, 135.0)

#: Plausible U-value ranges per component type [W/(m2 K)]. The lower limits are passive-house
#: levels, the upper ones single glazing (windows, doors) and uninsulated thin constructions
#: (opaque elements); see SIA 380/1 and ISO 10077 / ISO 6946 typical values.
U_VALUE_RANGES: dict[str, tuple[float, float]] = {
    "roof": (0.08, 4.0),
    "external_wall": (0.08, 4.0),
    "cellar_ceiling": (0.08, 4.0),
    "ground_floor": (0.08, 4.0),
    "window": (0.5, 6.0),
    "door": (0.3, 6.0),
    "attic_ceiling": (0.08, 4.0),
    "wall_to_unheated": (0.08, 4.0),
}

#: Plausibility ranges of scalar fields: (lower, upper, unit, lower inclusive, upper inclusive).
PLAUSIBLE_RANGES: dict[str, tuple[float, float, str, bool, bool]] = {
    "area": (0.0, 100_000.0, "m2", False, True),
    "tilt": (0.0, 180.0, "deg", True, True),
    "azimuth": (0.0, 360.0, "deg", True, True),
    "absorptance": (0.0, 1.0, "-", True, True),
    "g_value": (0.1, 0.9, "-", True, True),
    "frame_fraction": (0.0, 0.6, "-", True, True),
    "shading_factor": (0.0, 1.0, "-", True, True),
    "latitude": (-90.0, 90.0, "deg N", True, True),
    "longitude": (-180.0, 180.0, "deg E", True, True),
    "altitude": (-500.0, 9000.0, "m", True, True),
    "floors": (1, 10, "-", True, True),
    "heated_floor_area": (0.0, 1_000_000.0, "m2", False, True),
    "volume": (0.0, 10_000_000.0, "m3", False, True),
    "thermal_bridge_allowance": (0.0, 0.5, "W/(m2 K)", True, True),
    "air_change_rate": (0.05, 3.0, "1/h", False, False),
    "construction_year": (1000, 2100, "-", True, True),
    "perimeter": (0.0, 10_000.0, "m", False, True),
    "wall_thickness": (0.05, 1.5, "m", True, True),
    "soil_conductivity": (0.2, 4.5, "W/(m K)", True, True),
    "basement_depth": (0.0, 10.0, "m", True, True),
    "basement_wall_height_above_ground": (0.0, 5.0, "m", True, True),
    "basement_wall_u_value": (0.08, 4.0, "W/(m2 K)", True, True),
    "basement_floor_u_value": (0.08, 4.0, "W/(m2 K)", True, True),
    "basement_air_change_rate": (0.0, 5.0, "1/h", True, True),
    "basement_volume": (0.0, 1_000_000.0, "m3", False, True),
    "floor_area": (0.0, 1_000_000.0, "m2", False, True),
    "mean_storey_height": (1.5, 10.0, "m", True, True),
}

#: Compass names accepted for the azimuth, in degrees clockwise from north.
COMPASS_AZIMUTH: dict[str, float] = {
    name: 22.5 * i
    for i, name in enumerate(
        "N NNE NE ENE E ESE SE SSE S SSW SW WSW W WNW NW NNW".split()  # noqa: SIM905
    )
}

_HUMAN_TYPE = {
    "roof": "roof",
    "external_wall": "external wall",
    "window": "window",
    "door": "door",
    "cellar_ceiling": "cellar ceiling",
    "ground_floor": "ground floor",
    "attic_ceiling": "ceiling under an unheated attic",
    "wall_to_unheated": "wall to an unheated space",
}


# ----------------------------------------------------------------------------------------------
# plausibility checks with helpful messages
# ----------------------------------------------------------------------------------------------
def _format_number(value: float) -> str:
    return f"{value:g}"


def _inside(value: float, low: float, high: float, low_inc: bool, high_inc: bool) -> bool:
    above = value >= low if low_inc else value > low
    below = value <= high if high_inc else value < high
    return above and below


def _range_text(low: float, high: float, unit: str, low_inc: bool, high_inc: bool) -> str:
    unit_text = "" if unit == "-" else f" {unit}"
    if math.isinf(high) or high >= 1e5:
        return f"{'>=' if low_inc else '>'} {_format_number(low)}{unit_text}"
    if not low_inc:  # "0 to 10000 m" would read as if 0 were allowed
        return f"above {_format_number(low)} up to {_format_number(high)}{unit_text}"
    return f"{_format_number(low)} to {_format_number(high)}{unit_text}"


def _probable_typo(
    value: float, low: float, high: float, low_inc: bool, high_inc: bool, unit: str
) -> str:
    """A hint when a power-of-ten slip or a percentage would bring ``value`` into the range."""
    if value == 0 or not math.isfinite(value):
        return ""
    if unit == "m":
        reasons = {0.01: "centimetres instead of metres", 0.001: "millimetres instead of metres"}
    elif unit == "-":
        reasons = {0.01: "a percentage instead of a fraction"}
    else:
        reasons = {0.01: "a missing decimal point"}
    for factor in (0.01, 0.1, 0.001, 10.0, 100.0):
        if unit == "-" and factor < 1.0 and abs(value) <= 1.0:
            continue  # a fraction up to 1 is no slip (a window frame_fraction of 1: no glass)
        candidate = round(value * factor, 10)
        if _inside(candidate, low, high, low_inc, high_inc):
            reason = reasons.get(factor, "a misplaced decimal point")
            return f"; did you mean {_format_number(candidate)} ({reason})?"
    return ""


def _check_range(
    field: str,
    value: float | None,
    low: float,
    high: float,
    unit: str,
    *,
    what: str = "",
    low_inc: bool = True,
    high_inc: bool = True,
    hint: bool = True,
) -> None:
    """Raise a pydantic custom error naming field, value, allowed range and unit."""
    if value is None:
        return
    if not math.isfinite(value) or not _inside(value, low, high, low_inc, high_inc):
        unit_text = "" if unit == "-" else f" {unit}"
        typo = _probable_typo(value, low, high, low_inc, high_inc, unit) if hint else ""
        raise PydanticCustomError(
            "implausible_value",
            "{field} = {value}{unit} is outside the plausible range {range}{subject}{typo}",
            {
                "field": field,
                "value": _format_number(value),
                "unit": unit_text,
                "range": _range_text(low, high, unit, low_inc, high_inc),
                "subject": f" for {what}" if what else "",
                "typo": typo,
            },
        )


def _check_named_range(field: str, value: float | None, *, what: str = "") -> None:
    low, high, unit, low_inc, high_inc = PLAUSIBLE_RANGES[field]
    _check_range(field, value, low, high, unit, what=what, low_inc=low_inc, high_inc=high_inc)


class _Strict(BaseModel):
    """Base: unknown fields are errors (a misspelt field must not be silently ignored)."""

    model_config = ConfigDict(extra="forbid", frozen=True, str_strip_whitespace=True)

    @model_validator(mode="before")
    @classmethod
    def _suggest_field_names(cls, data: Any) -> Any:
        if isinstance(data, Mapping):
            known = set(cls.model_fields)
            for key in data:
                if isinstance(key, str) and key not in known:
                    close = difflib.get_close_matches(
                        key.replace("-", "_").lower(), sorted(known), n=1, cutoff=0.6
                    )
                    suggestion = f"; did you mean '{close[0]}'?" if close else ""
                    raise PydanticCustomError(
                        "unknown_field",
                        "unknown field '{key}'{suggestion} (allowed fields: {allowed})",
                        {"key": key, "suggestion": suggestion, "allowed": ", ".join(sorted(known))},
                    )
        return data


# ----------------------------------------------------------------------------------------------
# schema
# ----------------------------------------------------------------------------------------------
class Site(_Strict):
    """Where the building stands.

    Attributes
    ----------
    latitude : float [deg]
        Degrees north (negative south), -90 to 90.
    longitude : float [deg]
        Degrees east (negative west), -180 to 180.
    altitude : float [m]
        Height above sea level, default 0.
    timezone : str or float
        IANA name (``"Europe/Zurich"``) or fixed offset from UTC in hours (``1``). Measurements
        and weather are interpreted in it when their timestamps carry no offset.
    """

    latitude: float
    longitude: float
    altitude: float = 0.0
    timezone: str | float

    @field_validator("latitude", "longitude", "altitude")
    @classmethod
    def _plausible(cls, value: float, info) -> float:
        _check_named_range(info.field_name, value)
        return value

    @field_validator("timezone")
    @classmethod
    def _valid_timezone(cls, value: str | float) -> str | float:
        if isinstance(value, str):
            try:
                ZoneInfo(value)
            except (ZoneInfoNotFoundError, ValueError):
                try:
                    return float(value)
                except ValueError:
                    pass
                raise PydanticCustomError(
                    "timezone",
                    "timezone = '{value}' is not a known time-zone name; use an IANA name such as "
                    "'Europe/Zurich' or a fixed offset from UTC in hours such as 1",
                    {"value": value},
                ) from None
            return value
        _check_range("timezone", value, -12.0, 14.0, "h")
        return value


class Component(_Strict):
    """One envelope component (all components of one type and orientation may be lumped).

    Attributes
    ----------
    name : str
        Unique name, e.g. ``"wall south"``.
    type : {"roof", "external_wall", "window", "cellar_ceiling", "ground_floor", "door"}
    area : float [m2]
        Net area (windows: the whole window including frame; walls: without the windows).
    u_value : float [W/(m2 K)]
        Thermal transmittance. Plausible: windows 0.5-6, doors 0.3-6, opaque 0.08-4.
    tilt : float [deg]
        0 horizontal facing up, 90 vertical, 180 facing down. Default by type: roof 35,
        walls/windows/doors 90, cellar ceiling and ground floor 180.
    azimuth : float [deg] or compass name
        Direction the outer face looks to, clockwise from north (0 N, 90 E, 180 S, 270 W); compass
        names ("S", "SW", ...) are accepted. Required for tilted and vertical components; horizontal
        ones (tilt 0 or 180) default to 180 (irrelevant for them).
    absorptance : float [-]
        Solar absorptance of the outer surface (opaque components only), default 0.6.
    g_value : float [-]
        Total solar energy transmittance of the glazing at normal incidence (windows only,
        required), plausible 0.1-0.9.
    frame_fraction : float [-]
        Frame area over window area (windows only), default 0.3, plausible 0-0.6.
    shading_factor : float [-]
        Reduction factor for external shading, 1 = unshaded (windows only), default 1.0.
    b_factor : float [-]
        Temperature adjustment factor of ISO 13789 for a component towards an unheated space
        (``attic_ceiling``, ``wall_to_unheated`` only): its heat flow is ``b U A (Ti - Te)``.
        Default :data:`DEFAULT_B_FACTOR` (0.8 attic, 0.5 garage or staircase).

    References
    ----------
    .. [1] ISO 52016-1:2017, clause 6.5.13 (solar gains through windows: g-value, frame
       fraction, shading reduction).
    """

    name: str = Field(min_length=1)
    type: ComponentType
    area: float
    u_value: float
    tilt: float | None = None
    azimuth: float | None = None
    absorptance: float | None = None
    g_value: float | None = None
    frame_fraction: float | None = None
    shading_factor: float | None = None
    b_factor: float | None = None

    @field_validator("azimuth", mode="before")
    @classmethod
    def _compass_names(cls, value: Any) -> Any:
        if isinstance(value, str):
            key = value.strip().upper()
            if key in COMPASS_AZIMUTH:
                return COMPASS_AZIMUTH[key]
            try:
                return float(value)
            except ValueError:
                raise PydanticCustomError(
                    "azimuth",
                    "azimuth = '{value}' is neither a number of degrees clockwise from north nor a "
                    "compass name ({names})",
                    {"value": value, "names": ", ".join(COMPASS_AZIMUTH)},
                ) from None
        return value

    @model_validator(mode="after")
    def _plausible_and_complete(self) -> Component:
        kind = self.type
        what = f"a{'n' if kind[0] in 'aeiou' else ''} {_HUMAN_TYPE[kind]}"
        _check_named_range("area", self.area, what=what)
        low, high = U_VALUE_RANGES[kind]
        _check_range("u_value", self.u_value, low, high, "W/(m2 K)", what=what)
        tilt = DEFAULT_TILT[kind] if self.tilt is None else self.tilt
        _check_named_range("tilt", tilt)
        if kind in WALL_TYPES and not WALL_TILT[0] <= tilt <= WALL_TILT[1]:
            raise PydanticCustomError(
                "wall_tilt",
                "tilt = {tilt} deg for {what}: a wall stands between {low} and {high} deg (90 "
                "vertical){radians}; a component this flat is a roof, an attic ceiling or a "
                "floor: give it that type",
                {
                    "tilt": _format_number(tilt),
                    "what": what,
                    "low": _format_number(WALL_TILT[0]),
                    "high": _format_number(WALL_TILT[1]),
                    "radians": (
                        f"; {_format_number(tilt)} rad is {math.degrees(tilt):.0f} deg: write "
                        "degrees"
                        if 0.0 < tilt <= math.pi
                        else ""
                    ),
                },
            )
        if self.azimuth is not None and self.azimuth < 0 and self.azimuth >= -360:
            raise PydanticCustomError(
                "azimuth",
                "azimuth = {value} deg is outside 0 to 360 deg (clockwise from north: 0 N, 90 E, "
                "180 S, 270 W); did you mean {fixed} (a south-based or counter-clockwise "
                "convention)?",
                {
                    "value": _format_number(self.azimuth),
                    "fixed": _format_number(self.azimuth + 360),
                },
            )
        _check_named_range("azimuth", self.azimuth)
        azimuth = self.azimuth
        if azimuth is None:
            if tilt in (0.0, 180.0) or kind in UNHEATED_SPACE_TYPES:  # no sun reaches them
                azimuth = 180.0
            else:
                hint = " or tilt: 0 for a flat roof" if kind == "roof" else ""
                raise PydanticCustomError(
                    "missing_azimuth",
                    "azimuth is required for {what} with tilt {tilt} deg: give the direction its "
                    "outer face looks to in deg clockwise from north (0 N, 90 E, 180 S, 270 W) or "
                    "a compass name ('S', 'SW'){hint}",
                    {"what": what, "tilt": _format_number(tilt), "hint": hint},
                )
        object.__setattr__(self, "tilt", float(tilt))
        object.__setattr__(self, "azimuth", float(azimuth))
        if kind in UNHEATED_SPACE_TYPES:
            b = DEFAULT_B_FACTOR[kind] if self.b_factor is None else self.b_factor
            if not 0.0 < b <= 1.0:
                raise PydanticCustomError(
                    "b_factor",
                    "b_factor = {value} is outside 0 < b <= 1: the temperature adjustment "
                    "factor of ISO 13789, b = H_ue / (H_iu + H_ue), 1 = outdoor air, near 0 = a "
                    "space almost at indoor temperature (typical: attic 0.8, garage 0.5)",
                    {"value": _format_number(b)},
                )
            object.__setattr__(self, "b_factor", float(b))
        elif self.b_factor is not None:
            raise PydanticCustomError(
                "not_applicable",
                "b_factor applies to components towards an unheated space (attic_ceiling, "
                "wall_to_unheated), not to {what}",
                {"what": what},
            )

        if kind == "window":
            if self.absorptance is not None:
                raise PydanticCustomError(
                    "not_applicable",
                    "absorptance applies to opaque components only; a window's solar gain is set "
                    "by g_value, frame_fraction and shading_factor",
                )
            if self.g_value is None:
                raise PydanticCustomError(
                    "missing_g_value",
                    "g_value [-] is required for a window (typical: 0.75 single, 0.6-0.7 double, "
                    "0.5 triple glazing; plausible range 0.1 to 0.9)",
                )
            _check_named_range("g_value", self.g_value, what=what)
            frame = 0.3 if self.frame_fraction is None else self.frame_fraction
            _check_named_range("frame_fraction", frame, what=what)
            shading = 1.0 if self.shading_factor is None else self.shading_factor
            _check_named_range("shading_factor", shading)
            object.__setattr__(self, "frame_fraction", float(frame))
            object.__setattr__(self, "shading_factor", float(shading))
        else:
            for field in ("g_value", "frame_fraction", "shading_factor"):
                if getattr(self, field) is not None:
                    raise PydanticCustomError(
                        "not_applicable",
                        "{field} applies to windows only, not to {what}",
                        {"field": field, "what": what},
                    )
            absorptance = 0.6 if self.absorptance is None else self.absorptance
            _check_named_range("absorptance", absorptance)
            object.__setattr__(self, "absorptance", float(absorptance))
        return self

    @property
    def is_window(self) -> bool:
        """True for windows."""
        return self.type == "window"

    @property
    def is_opaque(self) -> bool:
        """True for roofs, walls, doors, cellar ceilings and ground floors."""
        return self.type in OPAQUE_TYPES

    @property
    def heat_transfer_coefficient(self) -> float:
        """U A of the component [W/K] (without thermal bridges); ``b U A`` towards an
        unheated space (ISO 13789:2017, 6.4.3)."""
        return self.u_value * self.area * (self.b_factor if self.b_factor is not None else 1.0)


class Ground(_Strict):
    """Ground and basement data for ISO 13370.

    Attributes
    ----------
    perimeter : float [m]
        Exposed perimeter P of the floor (heated building or basement).
    wall_thickness : float [m]
        Thickness w of the external walls at ground level, plausible 0.05-1.5 m.
    soil_conductivity : float [W/(m K)]
        Thermal conductivity of the unfrozen ground, default 2.0 (ISO 13370 Table 7: clay/silt
        1.5, sand/gravel 2.0, homogeneous rock 3.5).
    basement : {"unheated", "heated", "none"}
        Kind of basement; "none" is a slab on ground.
    basement_depth : float [m]
        Depth z of the basement floor below ground level, default 0.
    basement_wall_height_above_ground : float [m]
        Height h of the basement walls above ground level (unheated basement), default 0.
    basement_wall_u_value, basement_floor_u_value : float [W/(m2 K)] or None
        U-values of the basement walls and floor (unheated/heated basement), if known.
    basement_air_change_rate : float [1/h]
        Air change rate n of an unheated basement, default 0.3 (ISO 13370 clause H.3 default).
    basement_volume : float [m3] or None
        Air volume V of an unheated basement, if known.
    floor_area : float [m2] or None
        Ground floor area A; by default the summed area of the cellar ceiling and ground floor
        components (see :attr:`EnvelopeDescription.ground_floor_area`).

    References
    ----------
    .. [1] ISO 13370:2017, clauses 7 (characteristic dimension B'), 8 (slab on ground),
       9.2-9.3 (heated and unheated basement), Table 7 (soil conductivity).
    """

    perimeter: float
    wall_thickness: float
    soil_conductivity: float = 2.0
    basement: BasementType = "none"
    basement_depth: float = 0.0
    basement_wall_height_above_ground: float = 0.0
    basement_wall_u_value: float | None = None
    basement_floor_u_value: float | None = None
    basement_air_change_rate: float = 0.3
    basement_volume: float | None = None
    floor_area: float | None = None

    @model_validator(mode="after")
    def _plausible(self) -> Ground:
        for field in type(self).model_fields:
            value = getattr(self, field)
            if field in PLAUSIBLE_RANGES and value is not None:
                _check_named_range(field, value)
        if self.basement == "none" and self.basement_depth > 0:
            raise PydanticCustomError(
                "inconsistent",
                "basement_depth = {depth} m but basement = 'none' (slab on ground); set basement "
                "to 'unheated' or 'heated', or remove basement_depth",
                {"depth": _format_number(self.basement_depth)},
            )
        return self


class EnvelopeDescription(_Strict):
    """A building as an energy audit describes it (see the module docstring).

    Attributes
    ----------
    name : str
    location : Site
    floors : int
        Number of heated storeys, 1 to 10.
    heated_floor_area : float [m2]
        Energy reference area (SIA 416/1) or conditioned floor area.
    volume : float [m3]
        Heated air volume.
    emitter : {"radiators", "floor_heating", "convectors"}
    thermal_bridge_allowance : float [W/(m2 K)]
        Delta U added on the opaque envelope area for thermal bridges, default 0.05
        (ISO 13789 / SIA 380/1 simplified allowance), plausible 0 to 0.5.
    air_change_rate : float [1/h]
        Air change by infiltration and ventilation the description assumes, default 0.5 (the
        standard value for housing, EN 12831 / SIA 380/1); the median of the retrofit
        analysis' prior of the estimated extra loss ``H_est``. A blower-door test gives about
        ``n50 / 20`` (Sherman 1987); a mechanical ventilation its flow over the volume.
        Plausible above 0.05 and below 3.
    construction_year : int or None
    components : list of Component
        At least one; names unique.
    ground : Ground or None
    """

    name: str = Field(min_length=1)
    location: Site
    floors: int
    heated_floor_area: float
    volume: float
    emitter: EmitterType
    thermal_bridge_allowance: float = 0.05
    air_change_rate: float = 0.5
    construction_year: int | None = None
    components: list[Component] = Field(min_length=1)
    ground: Ground | None = None

    @model_validator(mode="after")
    def _plausible_and_consistent(self) -> EnvelopeDescription:
        for field in (
            "floors", "heated_floor_area", "volume", "thermal_bridge_allowance", "air_change_rate"
        ):
            _check_named_range(field, getattr(self, field))
        _check_named_range("construction_year", self.construction_year)
        height = self.volume / self.heated_floor_area
        low, high, *_ = PLAUSIBLE_RANGES["mean_storey_height"]
        if not low <= height <= high:
            raise PydanticCustomError(
                "inconsistent",
                "volume / heated_floor_area = {volume} m3 / {area} m2 = {height} m mean room "
                "height, outside the plausible {low} to {high} m; check both values (volume is "
                "the heated air volume in m3, heated_floor_area in m2)",
                {
                    "volume": _format_number(self.volume),
                    "area": _format_number(self.heated_floor_area),
                    "height": f"{height:.2f}",
                    "low": _format_number(low),
                    "high": _format_number(high),
                },
            )
        seen: dict[str, int] = {}
        for index, component in enumerate(self.components):
            if component.name in seen:
                raise PydanticCustomError(
                    "duplicate_name",
                    "components[{index}] name '{name}' is already used by components[{first}]; "
                    "component names must be unique",
                    {"index": index, "name": component.name, "first": seen[component.name]},
                )
            seen[component.name] = index
        has_cellar_ceiling = any(c.type == "cellar_ceiling" for c in self.components)
        if has_cellar_ceiling and self.ground is not None and self.ground.basement != "unheated":
            raise PydanticCustomError(
                "inconsistent",
                "a cellar_ceiling component is the floor over an unheated cellar, but "
                "ground.basement = '{basement}'; set ground.basement to 'unheated', or describe "
                "the floor as a ground_floor component (slab on ground, heated basement)",
                {"basement": self.ground.basement},
            )
        return self

    # ------------------------------------------------------------------ conveniences
    def components_of_type(self, component_type: str) -> list[Component]:
        """Components of one type, in file order.

        Parameters
        ----------
        component_type : str
            One of :data:`COMPONENT_TYPES`.
        """
        if component_type not in COMPONENT_TYPES:
            close = difflib.get_close_matches(component_type, COMPONENT_TYPES, n=1)
            suggestion = f"; did you mean '{close[0]}'?" if close else ""
            raise ThermocalInputError(
                f"unknown component type '{component_type}'{suggestion} "
                f"(known: {', '.join(COMPONENT_TYPES)})"
            )
        return [c for c in self.components if c.type == component_type]

    def component(self, name: str) -> Component:
        """The component called ``name``."""
        for candidate in self.components:
            if candidate.name == name:
                return candidate
        names = [c.name for c in self.components]
        close = [n for n in names if n.casefold() == name.casefold()]
        close = close or difflib.get_close_matches(name, names, n=1)
        suggestion = f"; did you mean '{close[0]}'?" if close else ""
        raise ThermocalInputError(
            f"building '{self.name}' has no component '{name}'{suggestion} (components: "
            f"{', '.join(names)})"
        )

    @property
    def windows(self) -> list[Component]:
        """The window components."""
        return self.components_of_type("window")

    @property
    def opaque_components(self) -> list[Component]:
        """Roofs, walls, doors, cellar ceilings and ground floors."""
        return [c for c in self.components if c.is_opaque]

    def area(self, component_type: str | None = None) -> float:
        """Summed area of the components of one type, or of all components [m2].

        Parameters
        ----------
        component_type : str or None
            One of :data:`COMPONENT_TYPES`; None sums the whole thermal envelope.
        """
        if component_type is None:
            return self.envelope_area
        return float(sum(c.area for c in self.components_of_type(component_type)))

    @cached_property
    def envelope_area(self) -> float:
        """Area of the whole thermal envelope, windows and ground components included [m2]."""
        return float(sum(c.area for c in self.components))

    @cached_property
    def opaque_area(self) -> float:
        """Area of the opaque envelope [m2] (the base of the thermal-bridge allowance)."""
        return float(sum(c.area for c in self.opaque_components))

    @cached_property
    def ground_floor_area(self) -> float:
        """Floor area towards the ground or basement [m2]: ``ground.floor_area`` if given, else
        the summed cellar ceiling and ground floor components."""
        if self.ground is not None and self.ground.floor_area is not None:
            return self.ground.floor_area
        return float(sum(c.area for c in self.components if c.type in GROUND_TYPES))

    @cached_property
    def thermal_bridge_heat_transfer_coefficient(self) -> float:
        """Thermal-bridge allowance times the opaque envelope area [W/K]."""
        return self.thermal_bridge_allowance * self.opaque_area

    def heat_transfer_coefficients(self) -> dict[str, float]:
        """U A summed per component type, plus ``"thermal_bridges"`` [W/K].

        Every component counts with its U A, towards an unheated attic or garage times its
        temperature adjustment factor b (ISO 13789); the reduced heat flow towards an unheated
        basement or the ground is ISO 13370's business
        (:mod:`thermocal.physics.ground`).
        """
        result = {
            kind: float(sum(c.heat_transfer_coefficient for c in self.components_of_type(kind)))
            for kind in COMPONENT_TYPES
        }
        result["thermal_bridges"] = self.thermal_bridge_heat_transfer_coefficient
        return result

    @cached_property
    def transmission_heat_transfer_coefficient(self) -> float:
        """Transmission heat transfer coefficient H_T = sum U A + Delta U_tb A_opaque [W/K].

        References
        ----------
        .. [1] ISO 13789:2017, clause 6.1 and 6.4 (simplified thermal-bridge allowance).
        """
        return float(sum(self.heat_transfer_coefficients().values()))

    @cached_property
    def mean_storey_height(self) -> float:
        """Heated volume over heated floor area [m]."""
        return self.volume / self.heated_floor_area


# ----------------------------------------------------------------------------------------------
# reading
# ----------------------------------------------------------------------------------------------
def _yaml_line_index(text: str) -> dict[tuple, int]:
    """Map every key path of a YAML document to the 1-based line where its value starts."""
    lines: dict[tuple, int] = {}
    try:
        root = yaml.compose(text, Loader=yaml.SafeLoader)
    except yaml.YAMLError:
        return lines

    def walk(node: yaml.Node, path: tuple) -> None:
        lines[path] = node.start_mark.line + 1
        if isinstance(node, yaml.MappingNode):
            for key_node, value_node in node.value:
                key = key_node.value
                lines[path + (key,)] = key_node.start_mark.line + 1
                walk(value_node, path + (key,))
                lines[path + (key,)] = key_node.start_mark.line + 1
        elif isinstance(node, yaml.SequenceNode):
            for index, item in enumerate(node.value):
                walk(item, path + (index,))

    if root is not None:
        walk(root, ())
    return lines


def _describe_location(loc: tuple, data: Any) -> str:
    """``components[2] ('wall south').u_value`` from a pydantic error location."""
    parts: list[str] = []
    node = data
    for item in loc:
        if isinstance(item, int):
            label = f"[{item}]"
            try:
                node = node[item]
                if isinstance(node, Mapping) and "name" in node:
                    label += f" ('{node['name']}')"
            except (IndexError, KeyError, TypeError):
                node = None
            parts.append(label)
        else:
            parts.append(("." if parts else "") + str(item))
            try:
                node = node[item] if isinstance(node, Mapping) else None
            except (KeyError, TypeError):
                node = None
    return "".join(parts) or "(top level)"


def _duplicate_name_error(
    ctx: Mapping[str, Any], lines: Mapping[tuple, int] | None
) -> tuple[tuple, str]:
    """Location and message of a component name used twice.

    The check runs on the whole building (pydantic locates it at the top level); the message
    points at the repeated name instead and names the component that has it first.

    Parameters
    ----------
    ctx : mapping
        The error's context: ``index`` and ``first`` (positions in ``components``) and
        ``name``.
    lines : mapping or None
        Key path -> 1-based line of a YAML file (:func:`_yaml_line_index`); None for other
        sources.

    Returns
    -------
    tuple
        The location ``("components", index, "name")`` and the message.
    """
    first = int(ctx["first"])
    line = (lines or {}).get(("components", first, "name"))
    at = f" (line {line})" if line else ""
    return ("components", int(ctx["index"]), "name"), (
        f"name '{ctx['name']}' is already used by components[{first}]{at}; component names "
        "must be unique: rename one of the two"
    )


def _format_validation_error(
    error: ValidationError, data: Any, source: str, lines: Mapping[tuple, int] | None = None
) -> str:
    messages = []
    for item in error.errors(include_url=False):
        loc = tuple(x for x in item["loc"] if not (isinstance(x, str) and x in _UNION_TAGS))
        message = item["msg"]
        if item["type"] == "duplicate_name":  # the model's check, located at the repeat
            loc, message = _duplicate_name_error(item["ctx"], lines)
        where = _describe_location(loc, data)
        line = None
        if lines:
            named = re.match(r"(\w+) (=|applies|\[)", item["msg"])
            probe = loc + (named.group(1),) if named and loc + (named.group(1),) in lines else loc
            while probe and probe not in lines:
                probe = probe[:-1]
            line = lines.get(probe)
        line_text = f" (line {line})" if line else ""
        if item["type"] == "missing":
            message = f"required field '{loc[-1] if loc else ''}' is missing"
        elif item["type"] == "literal_error":
            message = f"{message}, got {item.get('input')!r}"
        messages.append(f"  - {where}{line_text}: {message}")
    count = len(messages)
    header = f"{source}: invalid building description ({count} problem{'s' if count > 1 else ''})"
    return header + ":\n" + "\n".join(messages)


_UNION_TAGS = frozenset({"str", "float", "int", "function-after[_valid_timezone(), str]"})


def envelope_from_dict(
    data: Mapping[str, Any], *, source: str = "building description"
) -> EnvelopeDescription:
    """Validate a mapping into a :class:`EnvelopeDescription`, raising :class:`ThermocalInputError`.

    Same as ``EnvelopeDescription.model_validate(data)`` except that problems are raised as one
    :class:`~thermocal.errors.ThermocalInputError` listing every problem with its location.

    Parameters
    ----------
    data : mapping
        The building description (the content of a building file).
    source : str
        Name used in messages (the file path).
    """
    return _validate(data, source=source, lines=None)


#: Shipped examples of the two kinds of building file, named in the messages.
ENVELOPE_EXAMPLE = "examples/buildings/single_family_house_1953.yaml"
MULTIZONE_EXAMPLE = "examples/buildings/multizone_single_family_house.yaml"


def is_envelope_tree(data: Any) -> bool:
    """True for the content of an envelope description (components with areas and U-values)."""
    return isinstance(data, Mapping) and "components" in data and "zones" not in data


def is_multizone_tree(data: Any) -> bool:
    """True for the content of a multi-zone building file (zones, surfaces, constructions; or
    an IDF and parameters to change in it, as ``thermocal calibrate`` writes for an IDF)."""
    return (
        isinstance(data, Mapping)
        and ("zones" in data or "idf" in data)
        and "components" not in data
    )


def _validate(data: Any, *, source: str, lines: Mapping[tuple, int] | None) -> EnvelopeDescription:
    if is_multizone_tree(data):
        raise ThermocalInputError(
            f"{source} is a multi-zone building file (zones, surfaces, constructions, for "
            "thermocal simulate, identify and calibrate, or thermocal retrofit --detailed), not an "
            "envelope description (components with areas and U-values) that the retrofit "
            f"analysis' building: needs, e.g. {ENVELOPE_EXAMPLE} (format: docs/retrofit.md)"
        )
    if not isinstance(data, Mapping):
        raise ThermocalInputError(
            f"{source}: a building description must be a mapping of fields (name, location, "
            f"floors, ...), got {type(data).__name__}"
        )
    try:
        return EnvelopeDescription.model_validate(data)
    except ValidationError as error:
        raise ThermocalInputError(_format_validation_error(error, data, source, lines)) from None


def read_envelope(path: str | Path) -> EnvelopeDescription:
    """Read and validate a building file (``.yaml``/``.yml`` or ``.toml``).

    Parameters
    ----------
    path : str or Path
        The building file. The schema is that of :class:`EnvelopeDescription`; see
        ``examples/buildings/single_family_house_1953.yaml`` for a documented example.

    Returns
    -------
    EnvelopeDescription

    Raises
    ------
    ThermocalInputError
        The file is missing, not valid YAML/TOML, or fails validation. The message lists every
        problem with its location (field path, component name and, for YAML, the line number),
        the value, the plausible range with unit and, for likely typos, the value probably meant.
    """
    path = Path(path)
    if path.is_dir():
        raise ThermocalInputError(f"building file {path} is a folder, not a file")
    if not path.is_file():
        raise ThermocalInputError(f"building file {path} does not exist")
    suffix = path.suffix.lower()
    lines: dict[tuple, int] | None = None
    if suffix in (".yaml", ".yml"):
        from thermocal.io.yamlfile import read_yaml_text

        data, text = read_yaml_text(path, what="building file")
        lines = _yaml_line_index(text)
    elif suffix == ".toml":
        try:
            data = tomllib.loads(path.read_text(encoding="utf-8"))
        except UnicodeDecodeError as exc:
            raise ThermocalInputError(
                f"{path}: not a UTF-8 text file (byte {exc.start}); save the building file as UTF-8"
            ) from None
        except tomllib.TOMLDecodeError as exc:
            raise ThermocalInputError(f"{path}: not valid TOML: {exc}") from None
    else:
        raise ThermocalInputError(
            f"{path}: unknown building file type '{suffix}'; use .yaml, .yml or .toml"
        )
    if data is None:
        raise ThermocalInputError(f"{path}: the building file is empty")
    return _validate(data, source=str(path), lines=lines)


def write_envelope(building: EnvelopeDescription, path: str | Path) -> Path:
    """Write a building as a YAML file that :func:`read_envelope` reads back unchanged.

    Parameters
    ----------
    building : EnvelopeDescription
    path : str or Path
        Target file (``.yaml`` or ``.yml``); parent folders must exist.

    Returns
    -------
    Path
        The written file.
    """
    path = Path(path)
    if path.suffix.lower() not in (".yaml", ".yml"):
        raise ThermocalInputError(f"{path}: write_envelope writes YAML; use a .yaml file name")
    data = building.model_dump(mode="json", exclude_none=True)
    header = (
        f"# thermocal building file: {building.name}\n"
        "# Units: m, m2, m3, W/(m2 K), deg (azimuth clockwise from north, tilt 0 = facing up).\n"
    )
    path.write_text(header + yaml.safe_dump(data, sort_keys=False, allow_unicode=True))
    return path


#: The names before the envelope description and the multi-zone model got distinct names.
read_building = read_envelope
write_building = write_envelope
building_from_dict = envelope_from_dict
