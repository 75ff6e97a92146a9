"""In-situ U-values in the retrofit analysis: a heat-flux meter's log (ISO 9869-1's average
method, :mod:`thermocal.physics.heat_flux`) or a surveyed value becomes the prior of its
component's correction factor.

The heating data fix the house's total heat loss well and its split over the envelope poorly
(the groups stay prior-dominated on both EnergyPlus twins, docs/retrofit-twins.md); the split is
what each measure's saving depends on. An energy auditor measures the split directly: a
heat-flux plate on a wall for a week or two of winter gives that wall's U-value within some
7-10 % (ISO 9869-1 clause 9 puts a careful measurement at 14-28 % expanded). The calibration
then gives the component its own factor ``k`` with the prior
``ln k ~ N(ln(U_measured / U_described), s^2)``, ``s = sqrt(ln(1 + r^2))`` from the
measurement's relative standard uncertainty ``r``; the other components keep their group's.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from thermocal.errors import ThermocalInputError
from thermocal.physics.heat_flux import InSituUValue, average_method

__all__ = ["InSituMeasurement", "in_situ_priors", "measure_in_situ"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class InSituMeasurement:
    """One component's in-situ U-value against its description.

    Attributes
    ----------
    component : str
        ``walls``, ``roof``, ``attic_ceiling``, ``wall_to_unheated`` or ``cellar_ceiling``.
    described_u : float
        The building file's U-value of the measured construction [W/(m2 K)].
    result : InSituUValue
        The measured value and its standard uncertainty.
    source : str
        The log file and method, or "given".
    """

    component: str
    described_u: float
    result: InSituUValue
    source: str

    @property
    def ratio(self) -> float:
        """Measured over described U [-]."""
        return self.result.u_value / self.described_u

    @property
    def prior(self) -> tuple[float, float]:
        """Mean and standard deviation of the component factor's ``ln k`` [-]."""
        return float(np.log(self.ratio)), float(np.sqrt(np.log1p(self.result.rel_std**2)))

    def as_dict(self) -> dict:
        """JSON-ready form (results.json ``in_situ``)."""
        return {
            "source": self.source,
            "described_u_W_per_m2K": self.described_u,
            "measured_over_described": self.ratio,
            **self.result.as_dict(),
        }


def in_situ_priors(measurements: dict[str, InSituMeasurement]) -> dict[str, tuple[float, float]]:
    """Component -> (mean, standard deviation) of its factor's ``ln k`` (the model's
    ``in_situ``)."""
    return {c: m.prior for c, m in measurements.items()}


def _described_u(building, component: str, spec) -> float:
    """The U-value [W/(m2 K)] of the construction the plate was on."""
    from thermocal.retrofit.config import IN_SITU_COMPONENTS

    kind = IN_SITU_COMPONENTS[component][1]
    of_kind = [c for c in building.components if c.type == kind]
    where = f"in_situ.{component}"
    if not of_kind:
        raise ThermocalInputError(
            f"{where}: building {building.name!r} has no {kind} component to measure; remove "
            f"the entry or add the component to the building file"
        )
    if spec.component is not None:
        named = [c for c in of_kind if c.name == spec.component]
        if not named:
            raise ThermocalInputError(
                f"{where}.component {spec.component!r} is not a {kind} of building "
                f"{building.name!r} (its {kind} components: {[c.name for c in of_kind]})"
            )
        return float(named[0].u_value)
    values = sorted({round(float(c.u_value), 6) for c in of_kind})
    if len(values) > 1:
        raise ThermocalInputError(
            f"{where}: the building's {kind} components have different U-values {values}; say "
            f"which one the plate was on with {where}.component (one of "
            f"{[c.name for c in of_kind]})"
        )
    return float(of_kind[0].u_value)


def _read_log(spec, component: str, default_tz):
    """The log's time stamps, outward heat flux [W/m2] and temperatures [C]."""
    from thermocal.io.measurements import read_measurements
    from thermocal.retrofit.data import _timezone

    path = Path(spec.file)
    where = f"in_situ.{component}"
    if not path.is_file():
        raise ThermocalInputError(f"heat-flux log {path} not found ({where}.file)")
    names = {col: std for std, col in spec.columns.items()}
    units = {
        spec.columns["heat_flux"]: "W/m2",
        spec.columns["temp_in"]: spec.temperature_unit,
        spec.columns["temp_out"]: spec.temperature_unit,
    }
    try:
        raw, _ = read_measurements(
            path, layout="wide", time_column=spec.time_column, sensors=names, units=units,
            tz=_timezone(spec.timezone) or _timezone(default_tz), rows="interval_start",
            unknown_sensors="ignore",
        )  # fmt: skip
    except ThermocalInputError as exc:
        text = str(exc)
        if "look like Kelvin" in text or "look like Fahrenheit" in text:
            text += f" (here: {where}.temperature_unit)"
        raise ThermocalInputError(f"{where}: {text}") from None
    q = raw["heat_flux"].to_numpy(float)
    if spec.heat_flux_sign == "inward":
        q = -q
    ti, te = raw["temp_in"].to_numpy(float), raw["temp_out"].to_numpy(float)
    for std, values in (("temp_in", ti), ("temp_out", te)):
        high = np.nanmax(values) if np.isfinite(values).any() else np.nan
        if np.isfinite(high) and high > 60.0:
            guess = "Kelvin" if high > 250.0 else "Fahrenheit"
            raise ThermocalInputError(
                f"heat-flux log {path}: column {spec.columns[std]!r} ({where}.columns.{std}) "
                f"reaches {high:.1f} {spec.temperature_unit}; {guess}? Set "
                f"{where}.temperature_unit"
            )
    return raw.index, q, ti, te


def measure_in_situ(cfg, building, default_tz=None) -> dict[str, InSituMeasurement]:
    """Every configured in-situ U-value (``cfg.in_situ``), checked.

    Parameters
    ----------
    cfg : RetrofitConfig
    building : thermocal.io.envelope.EnvelopeDescription
    default_tz : str or float, optional
        Time zone of log time stamps without offset when the entry gives none.

    Returns
    -------
    dict component -> InSituMeasurement

    Raises
    ------
    ThermocalInputError
        A log missing or unreadable, a heat flux whose mean points inwards in winter (the
        plate's sign), a log that fails ISO 9869-1's criteria (measure longer, or give the
        value with its uncertainty), a component the building lacks.
    """
    from thermocal.retrofit.config import IN_SITU_COMPONENTS

    out: dict[str, InSituMeasurement] = {}
    for component, spec in cfg.in_situ.items():
        where = f"in_situ.{component}"
        described = _described_u(building, component, spec)
        if spec.file is None:
            result = InSituUValue(u_value=float(spec.u_value), rel_std=float(spec.rel_std))
            out[component] = InSituMeasurement(component, described, result, "given")
            continue
        times, q, ti, te = _read_log(spec, component, default_tz)
        mean_q = float(np.nanmean(q))
        if mean_q < 0 and float(np.nanmean(ti - te)) > 0:
            raise ThermocalInputError(
                f"heat-flux log {spec.file}: the heat flux is {mean_q:.1f} W/m2 on average "
                "(inwards) while the inside is warmer: the plate reports the other direction; "
                f"set {where}.heat_flux_sign: inward"
            )
        try:
            result = average_method(
                times, q, ti, te, temperatures=spec.temperatures,
                flow=IN_SITU_COMPONENTS[component][0], plate_rel_std=spec.plate_rel_std,
                temperature_std_K=spec.temperature_std, spot_rel_std=spec.spot_rel_std,
                areal_heat_capacity=None if spec.areal_heat_capacity is None
                else 1e3 * spec.areal_heat_capacity,
            )  # fmt: skip
        except ValueError as exc:
            raise ThermocalInputError(f"heat-flux log {spec.file} ({where}): {exc}") from None
        if not result.converged:
            raise ThermocalInputError(
                f"heat-flux log {spec.file} ({where}): the average method of ISO 9869-1 has not "
                f"converged ({'; '.join(result.failed())}): log longer (whole days of winter), "
                f"or give {where}.u_value with a rel_std that covers the spread"
            )
        for note in result.notes:
            log.info("%s: %s", where, note)
        source = f"{Path(spec.file).name}: ISO 9869-1 average method, {result.days} days"
        out[component] = InSituMeasurement(component, described, result, source)
    return out
