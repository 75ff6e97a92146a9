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

from dataclasses import dataclass

import numpy as np

from thermocal.errors import ThermocalInputError
from thermocal.io.heat_flux_log import measure_in_situ_value
from thermocal.physics.heat_flux import InSituUValue

__all__ = ["InSituMeasurement", "in_situ_priors", "measure_in_situ"]


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
    from thermocal.retrofit.correction import FACTOR_BOUNDS

    out: dict[str, InSituMeasurement] = {}
    for component, spec in cfg.in_situ.items():
        where = f"in_situ.{component}"
        described = _described_u(building, component, spec)
        for key in ("flow", "other_side"):
            if getattr(spec, key) is not None:
                raise ThermocalInputError(
                    f"{where}.{key}: the component sets the heat flow's direction and what is "
                    f"on its other side ({component}); remove the key"
                )
        if spec.resistance is not None:
            raise ThermocalInputError(
                f"{where}: give the component's U-value (u_value, air to air) rather than its "
                "resistance: the building file describes U-values"
            )
        flow, _, films = IN_SITU_COMPONENTS[component]
        result, source = measure_in_situ_value(
            spec, where, flow=flow, surface_resistances=films, default_tz=default_tz
        )
        measurement = InSituMeasurement(component, described, result, source)
        low, high = FACTOR_BOUNDS
        if not low <= measurement.ratio <= high:
            raise ThermocalInputError(
                f"{where}: the measured U-value {result.u_value:.3g} W/(m2 K) is "
                f"{measurement.ratio:.2f} times the building file's {described:.3g}, beyond "
                f"the range the data may correct ({low:g}-{high:g} times): check the log "
                "(plate position, the temperatures' sides) or correct the building file's "
                "U-value"
            )
        out[component] = measurement
    return out
