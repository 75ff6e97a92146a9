"""Declaring a grey-box RC model: states, conductances, heat inputs, outputs, noise, parameters.

A model is declared as an RC network (never as matrices), in Python or in a YAML model file with
the same structure (see ``docs/model-file.md``)::

    name: TiTe
    states:
      Ti: {capacity: Ci, noise: sigma_i, initial_mean: Ti0, initial_std: 1.0}
      Te: {capacity: Ce, noise: sigma_e, initial_mean: Te0, initial_std: 2.0}
    conductances:
      - {between: [Ti, Te], resistance: Rie}
      - {between: [Te, Ta], resistance: Rea}      # Ta: a boundary-temperature data column
    heat_inputs:
      - {column: Ph, unit: kW, into: Ti}
      - {column: Ps, unit: kW/m2, into: Ti, scale: Aw}
    outputs:
      - {column: yTi, state: Ti, noise: e_std}
    parameters:
      Ci: {value: 1.0, lower: 1.0e-5, upper: 20, unit: kWh/K}
      ...

Wherever a parameter name is expected a plain number is accepted too; it is then a constant in SI
units (J/K, W/K, K/W, K/sqrt(s), C, K, m2, -).

Order of the input vector ``u`` (:attr:`RCModel.input_names`): the boundary-temperature columns in
order of first appearance in ``conductances``, then the heat-input columns in order of first
appearance in ``heat_inputs``.
"""

from __future__ import annotations

import copy
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from thermocal.errors import ThermocalInputError
from thermocal.statespace import kernels
from thermocal.statespace.units import UNIT_KIND, parameter_si_factor

_TOP_LEVEL_KEYS = {
    "name",
    "description",
    "states",
    "conductances",
    "heat_inputs",
    "outputs",
    "parameters",
    "derived",
    "columns",
}
_STATE_KEYS = {"capacity", "noise", "initial_mean", "initial_std", "description"}
_CONDUCTANCE_KEYS = {"between", "conductance", "resistance", "description"}
_HEAT_KEYS = {"column", "into", "scale", "unit", "description", "allow_negative"}
_OUTPUT_KEYS = {"column", "state", "states", "noise", "description"}
_PARAMETER_KEYS = {"value", "lower", "upper", "fixed", "unit", "description", "prior"}

#: Unit kinds allowed for each role a parameter can play.
_ROLE_KINDS = {
    "capacity": {"capacity"},
    "conductance": {"conductance"},
    "resistance": {"resistance"},
    "noise": {"diffusion"},
    "measurement noise": {"temperature"},
    "initial mean": {"temperature"},
    "initial std": {"temperature"},
    "scale": {"area", "dimensionless"},
    "fraction": {"dimensionless"},
}
_POSITIVE_ROLES = {"capacity", "conductance", "resistance"}
_NONNEGATIVE_ROLES = {"noise", "measurement noise", "initial std"}

#: ``"2*H_env"``: a positive number times a parameter, allowed in conductance/resistance lists.
_FACTOR_PATTERN = re.compile(r"^\s*([0-9.eE+-]+)\s*\*\s*([A-Za-z_][\w./-]*)\s*$")

#: An initial mean above this [C] is taken for kelvin by mistake.
KELVIN_INITIAL_MEAN = 150.0

#: Default initial-state standard deviation [K] when a state declares none.
DEFAULT_INITIAL_STD = 1.0


@dataclass
class Parameter:
    """One model parameter, in its declared unit.

    Parameters
    ----------
    name : str
        Parameter name.
    value : float [unit]
        Initial (or fixed) value.
    unit : str
        Declared unit (see :data:`thermocal.statespace.units.PARAMETER_UNITS`).
    lower, upper : float [unit]
        Bounds; the optimiser keeps the estimate strictly inside them.
    fixed : bool
        Fixed parameters are not estimated.
    """

    name: str
    value: float
    unit: str
    lower: float = -math.inf
    upper: float = math.inf
    fixed: bool = False
    description: str = ""
    #: True when ``lower`` was not given; it is then set to 0 for positive quantities.
    auto_lower: bool = field(default=False, repr=False)
    #: Prior: ``("normal", mean, std)``, ``("lognormal", median, std_log)`` or
    #: ``("uniform", lower, upper)`` in the declared unit; None for none (see :meth:`log_prior`).
    prior: tuple | None = None

    def log_prior(self, x: float) -> tuple[float, float]:
        """Log prior density at ``x`` [declared unit] and its derivative d/dx.

        normal(mean, std); lognormal(median, std_log): ``ln x ~ N(ln median, std_log^2)``;
        uniform: ``1 / (upper - lower)`` within the bounds.
        """
        kind, a, b = self.prior
        if kind == "normal":
            z = (x - a) / b
            return -0.5 * z * z - math.log(b * math.sqrt(2 * math.pi)), -z / b
        if kind == "lognormal":
            if x <= 0:
                return -math.inf, 0.0
            z = (math.log(x) - math.log(a)) / b
            return (
                -0.5 * z * z - math.log(x * b * math.sqrt(2 * math.pi)),
                -z / (b * x) - 1.0 / x,
            )
        return -math.log(b - a), 0.0

    @property
    def si_factor(self) -> float:
        """Factor from the declared unit to SI [-]."""
        return parameter_si_factor(self.unit, parameter=self.name)

    @property
    def transform(self) -> int:
        """Kind of unconstrained transform (see :mod:`thermocal.statespace.kernels`)."""
        lo_finite, hi_finite = math.isfinite(self.lower), math.isfinite(self.upper)
        if lo_finite and hi_finite:
            return kernels.TRANSFORM_LOGIT
        if lo_finite:
            return kernels.TRANSFORM_LOG
        if hi_finite:
            return kernels.TRANSFORM_NEGLOG
        return kernels.TRANSFORM_IDENTITY

    def to_unconstrained(self, value: float) -> float:
        """Unconstrained value ``theta`` of a declared-unit ``value``."""
        kind = self.transform
        if kind == kernels.TRANSFORM_LOG:
            return math.log(value - self.lower)
        if kind == kernels.TRANSFORM_NEGLOG:
            return math.log(self.upper - value)
        if kind == kernels.TRANSFORM_LOGIT:
            p = (value - self.lower) / (self.upper - self.lower)
            return math.log(p) - math.log1p(-p)
        return float(value)

    def from_unconstrained(self, theta: float) -> float:
        """Declared-unit value of an unconstrained ``theta``."""
        return float(kernels.to_natural(theta, self.transform, self.lower, self.upper))

    def derivative(self, theta: float) -> float:
        """d value / d theta [unit], for the delta method."""
        kind = self.transform
        if kind in (kernels.TRANSFORM_LOG, kernels.TRANSFORM_NEGLOG):
            return math.exp(theta) * (1.0 if kind == kernels.TRANSFORM_LOG else -1.0)
        if kind == kernels.TRANSFORM_LOGIT:
            p = (
                1.0 / (1.0 + math.exp(-theta))
                if theta >= 0
                else math.exp(theta) / (1 + math.exp(theta))
            )
            return (self.upper - self.lower) * p * (1.0 - p)
        return 1.0

    def to_dict(self) -> dict[str, Any]:
        """Model-file representation."""
        out: dict[str, Any] = {"value": self.value, "unit": self.unit}
        if self.prior is not None:
            kind, a, b = self.prior
            out["prior"] = "uniform" if kind == "uniform" else {kind: [a, b]}
        if math.isfinite(self.lower):
            out["lower"] = self.lower
        if math.isfinite(self.upper):
            out["upper"] = self.upper
        if self.fixed:
            out["fixed"] = True
        if self.description:
            out["description"] = self.description
        return out


@dataclass
class Structure:
    """Compiled model structure: index arrays into the value vector (parameters then constants)."""

    arrays: tuple
    C: np.ndarray
    n_states: int
    n_inputs: int
    constants: np.ndarray
    roles: dict[str, set[str]] = field(default_factory=dict)


def _as_float(value: Any, what: str) -> float:
    try:
        return float(value)
    except (TypeError, ValueError):
        raise ThermocalInputError(f"{what}: '{value}' is not a number") from None


class RCModel:
    """A continuous-time stochastic RC model ``dx = (A x + B u) dt + Sigma dw``, ``y = C x + e``.

    Build it from a model file (:meth:`from_yaml`), a dictionary of the same structure
    (:meth:`from_dict`), or step by step (:meth:`add_state`, :meth:`add_conductance`,
    :meth:`add_heat_input`, :meth:`add_output`, :meth:`add_parameter`). Nothing is computed until
    the model is used; every use validates the declaration first.

    Parameters
    ----------
    name : str
        Model name (used in reports).
    description : str
        Free text.
    """

    def __init__(self, name: str = "model", description: str = "") -> None:
        self.name = name
        self.description = description
        self._states: dict[str, dict[str, Any]] = {}
        self._conductances: list[dict[str, Any]] = []
        self._heat_inputs: list[dict[str, Any]] = []
        self._outputs: list[dict[str, Any]] = []
        self.parameters: dict[str, Parameter] = {}
        #: Derived quantities: name -> (expression in parameter names, unit).
        self.derived: dict[str, tuple[str, str]] = {}
        self._structure: Structure | None = None
        self.source = "<in memory>"
        #: Model column name -> data column name (the model file's ``columns:`` section).
        self.columns: dict[str, str] = {}
        #: Initial means of the periods after the first ({state: parameter or number [C]}),
        #: when the likelihood is split at long gaps (see :meth:`with_periods`).
        self.period_initial_means: list[dict[str, str | float]] = []

    # ------------------------------------------------------------------ declaration
    def add_state(
        self,
        name: str,
        *,
        capacity: str | float | None,
        noise: str | float | None = None,
        initial_mean: str | float | None = None,
        initial_std: str | float | None = None,
    ) -> RCModel:
        """Declare a node temperature [C] with its heat capacity and noise.

        Parameters
        ----------
        name : str
            State name.
        capacity : str or float [J/K]
            Heat-capacity parameter (or SI constant).
        noise : str or float [K/sqrt(s)], optional
            Diffusion standard deviation of the state (``dx = f dt + sigma dw``); 0 if omitted.
        initial_mean : str or float [C]
            Mean of the state at the first sample.
        initial_std : str or float [K], optional
            Standard deviation of the state at the first sample (default 1 K).
        """
        if name in self._states:
            raise ThermocalInputError(f"model '{self.name}': state '{name}' is declared twice")
        self._states[name] = {
            "capacity": capacity,
            "noise": noise,
            "initial_mean": initial_mean,
            "initial_std": initial_std,
        }
        self._structure = None
        return self

    def add_conductance(
        self,
        a: str,
        b: str,
        *,
        conductance: str | float | Sequence[str | float] | None = None,
        resistance: str | float | Sequence[str | float] | None = None,
    ) -> RCModel:
        """Connect two states, or a state and a boundary-temperature column, by a heat path.

        Parameters
        ----------
        a, b : str
            State names; a name that is not a state is a boundary-temperature data column [C].
        conductance : str, float or list [W/K]
            Heat transfer coefficient; a list is a series connection ``1 / sum(1/H)``. An item
            may be ``"2*H"`` (a positive number times a parameter), e.g. half a wall
            ``[He, "2*H_wall"]``.
        resistance : str, float or list [K/W]
            Thermal resistance; a list is a series connection ``sum(R)`` (items as above).
        """
        self._conductances.append(
            {"between": [a, b], "conductance": conductance, "resistance": resistance}
        )
        self._structure = None
        return self

    def add_heat_input(
        self,
        column: str,
        *,
        into: str | Mapping[str, str | float],
        scale: str | float | None = None,
        unit: str = "W",
        allow_negative: bool = False,
    ) -> RCModel:
        """Inject a heat-flow data column into one or several states.

        Parameters
        ----------
        column : str
            Data column, in ``unit``.
        into : str or mapping
            A state name, or ``{state: fraction}`` with fractions as numbers, parameter names or
            ``"rest"`` (one minus the other fractions).
        scale : str or float [m2 or -], optional
            Parameter multiplying the column (e.g. an effective solar aperture ``Aw`` [m2]).
        unit : str
            Unit of the column: ``W``, ``kW``, ``MW``, ``W/m2``, ``kW/m2``.
        allow_negative : bool
            The column is a heat flow that is negative by nature (a ventilation or extraction
            heat flow, cooling): its negative values are not flagged.
        """
        spec = {"column": column, "into": into, "scale": scale, "unit": unit}
        if allow_negative:
            spec["allow_negative"] = True
        self._heat_inputs.append(spec)
        self._structure = None
        return self

    def add_output(
        self,
        column: str,
        *,
        state: str | None = None,
        states: Mapping[str, float] | None = None,
        noise: str | float,
    ) -> RCModel:
        """Declare an observed data column [C] = a state (or a linear combination) + noise.

        Parameters
        ----------
        column : str
            Data column of the measurement [C].
        state : str, optional
            The observed state.
        states : mapping, optional
            ``{state: coefficient}`` for a linear combination (coefficients are numbers).
        noise : str or float [K]
            Measurement standard deviation.
        """
        self._outputs.append({"column": column, "state": state, "states": states, "noise": noise})
        self._structure = None
        return self

    def add_parameter(
        self,
        name: str,
        value: float,
        *,
        unit: str,
        lower: float | None = None,
        upper: float | None = None,
        fixed: bool = False,
        description: str = "",
        prior: Mapping[str, Any] | str | None = None,
    ) -> RCModel:
        """Declare a parameter with its initial value, unit, bounds and whether it is fixed.

        Parameters
        ----------
        name : str
            Parameter name.
        value : float [unit]
            Initial value (the value itself when ``fixed``).
        unit : str
            Declared unit, e.g. ``kWh/K``, ``W/K``, ``K/kW``, ``m2``, ``K/sqrt(h)``, ``C``, ``K``.
        lower, upper : float [unit], optional
            Bounds (default: 0 and +inf for capacities, conductances, resistances and standard
            deviations; unbounded otherwise).
        fixed : bool
            Keep the value fixed during estimation.
        prior : mapping or "uniform", optional
            Prior density for maximum a posteriori estimation, in the declared unit:
            ``{"normal": [mean, std]}``, ``{"lognormal": [median, std_log]}`` (``ln x`` normal)
            or ``"uniform"`` (flat within both bounds).
        """
        if name in self.parameters:
            raise ThermocalInputError(f"model '{self.name}': parameter '{name}' is declared twice")
        parameter_si_factor(unit, parameter=name)
        value = _as_float(value, f"parameter '{name}' value")
        kind = UNIT_KIND[unit]
        default_lower = (
            0.0 if kind in {"capacity", "conductance", "resistance", "diffusion"} else -math.inf
        )
        self.parameters[name] = Parameter(
            name=name,
            value=value,
            unit=unit,
            lower=default_lower if lower is None else _as_float(lower, f"parameter '{name}' lower"),
            upper=math.inf if upper is None else _as_float(upper, f"parameter '{name}' upper"),
            fixed=bool(fixed),
            description=description,
            auto_lower=lower is None,
        )
        if prior is not None:
            self.parameters[name].prior = _parse_prior(self.parameters[name], prior, self.name)
        self._structure = None
        return self

    def add_derived(self, name: str, expression: str, *, unit: str = "") -> RCModel:
        """Declare a derived quantity, estimated with a delta-method standard error.

        Parameters
        ----------
        name : str
            Name, e.g. ``heat_loss_coefficient``.
        expression : str
            Arithmetic of parameter names in their declared units and numbers: ``+ - * / **``,
            parentheses, ``sqrt``, ``exp``, ``log``, ``abs``, e.g. ``1/Ria + 1/(Rie + Rea)``.
        unit : str
            The unit of the result (free text, for the report), e.g. ``kW/K``.
        """
        if name in self.derived:
            raise ThermocalInputError(f"model '{self.name}': derived '{name}' is declared twice")
        unknown = sorted(_expression_names(str(expression), f"derived '{name}'"))
        unknown = [n for n in unknown if n not in self.parameters]
        if unknown:
            raise ThermocalInputError(
                f"model '{self.name}': derived '{name}' = {expression!r} uses "
                f"{', '.join(map(repr, unknown))}, not a parameter (parameters: "
                f"{', '.join(self.parameters)})"
            )
        self.derived[str(name)] = (str(expression), str(unit))
        return self

    def derived_values(self, params: Mapping[str, float] | None = None) -> dict[str, float]:
        """Derived quantities at ``params`` [declared units] (default: the declared values)."""
        values = {n: p.value for n, p in self.parameters.items()}
        values.update({k: float(v) for k, v in (params or {}).items()})
        return {n: evaluate_expression(e, values) for n, (e, _) in self.derived.items()}

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_dict(cls, spec: Mapping[str, Any], *, source: str = "<dict>") -> RCModel:
        """Build a model from a dictionary with the structure of the model file.

        Parameters
        ----------
        spec : mapping
            Keys ``name``, ``description``, ``states``, ``conductances``, ``heat_inputs``,
            ``outputs``, ``parameters`` (see ``docs/model-file.md``).
        source : str
            Where the specification came from, used in error messages.
        """
        if not isinstance(spec, Mapping):
            raise ThermocalInputError(f"{source}: a model file must be a mapping of sections")
        unknown = set(spec) - _TOP_LEVEL_KEYS
        if unknown:
            raise ThermocalInputError(
                f"{source}: unknown section(s) {sorted(unknown)}; "
                f"allowed: {sorted(_TOP_LEVEL_KEYS)}"
            )
        model = cls(
            name=str(spec.get("name", "model")), description=str(spec.get("description", ""))
        )
        model.source = source
        where = f"{source} (model '{model.name}')"

        params = spec.get("parameters") or {}
        if not isinstance(params, Mapping):
            raise ThermocalInputError(f"{where}: 'parameters' must map names to settings")
        for pname, pspec in params.items():
            if not isinstance(pspec, Mapping):
                raise ThermocalInputError(
                    f"{where}: parameter '{pname}' must be a mapping with value, unit "
                    "(and optional lower, upper, fixed)"
                )
            _check_keys(pspec, _PARAMETER_KEYS, f"{where}: parameter '{pname}'")
            for key in ("value", "unit"):
                if key not in pspec:
                    raise ThermocalInputError(f"{where}: parameter '{pname}' has no '{key}'")
            if not isinstance(pspec.get("fixed", False), bool):
                raise ThermocalInputError(
                    f"{where}: parameter '{pname}': 'fixed' must be true or false, got "
                    f"{pspec['fixed']!r}"
                )
            try:
                model.add_parameter(
                    str(pname),
                    pspec["value"],
                    unit=str(pspec["unit"]),
                    lower=pspec.get("lower"),
                    upper=pspec.get("upper"),
                    fixed=bool(pspec.get("fixed", False)),
                    description=str(pspec.get("description", "")),
                    prior=pspec.get("prior"),
                )
            except ThermocalInputError as exc:  # name the file as well
                raise ThermocalInputError(f"{where}: {exc}") from None

        states = spec.get("states") or {}
        if isinstance(states, Sequence) and not isinstance(states, str):
            for i, s in enumerate(states):
                if not isinstance(s, Mapping) or not s.get("name"):
                    raise ThermocalInputError(
                        f"{where}: states[{i}] needs a 'name' (or declare the states as a "
                        "mapping name -> settings)"
                    )
            states = {s["name"]: {k: v for k, v in s.items() if k != "name"} for s in states}
        if not isinstance(states, Mapping) or not states:
            raise ThermocalInputError(f"{where}: 'states' must declare at least one state")
        for sname, sspec in states.items():
            sspec = sspec or {}
            _check_keys(sspec, _STATE_KEYS, f"{where}: state '{sname}'")
            model.add_state(
                str(sname),
                capacity=sspec.get("capacity"),
                noise=sspec.get("noise"),
                initial_mean=sspec.get("initial_mean"),
                initial_std=sspec.get("initial_std"),
            )
        for i, cspec in enumerate(spec.get("conductances") or []):
            _check_keys(cspec, _CONDUCTANCE_KEYS, f"{where}: conductances[{i}]")
            between = cspec.get("between")
            if not isinstance(between, Sequence) or isinstance(between, str) or len(between) != 2:
                raise ThermocalInputError(
                    f"{where}: conductances[{i}] needs 'between: [node, node]' (two names)"
                )
            model.add_conductance(
                str(between[0]),
                str(between[1]),
                conductance=cspec.get("conductance"),
                resistance=cspec.get("resistance"),
            )
        for i, hspec in enumerate(spec.get("heat_inputs") or []):
            _check_keys(hspec, _HEAT_KEYS, f"{where}: heat_inputs[{i}]")
            if "column" not in hspec or "into" not in hspec:
                raise ThermocalInputError(f"{where}: heat_inputs[{i}] needs 'column' and 'into'")
            model.add_heat_input(
                str(hspec["column"]),
                into=hspec["into"],
                scale=hspec.get("scale"),
                unit=str(hspec.get("unit", "W")),
                allow_negative=bool(hspec.get("allow_negative", False)),
            )
        for i, ospec in enumerate(spec.get("outputs") or []):
            _check_keys(ospec, _OUTPUT_KEYS, f"{where}: outputs[{i}]")
            if "column" not in ospec or "noise" not in ospec:
                raise ThermocalInputError(
                    f"{where}: outputs[{i}] needs 'column' and 'noise' (measurement std)"
                )
            model.add_output(
                str(ospec["column"]),
                state=ospec.get("state"),
                states=ospec.get("states"),
                noise=ospec["noise"],
            )
        columns = spec.get("columns") or {}
        if not isinstance(columns, Mapping) or not all(
            isinstance(v, str) and v.strip() for v in columns.values()
        ):
            raise ThermocalInputError(
                f"{where}: 'columns' must map the model's column names to data column names, "
                "e.g. columns: {Ph: heating_kW, yTi: T_living}"
            )
        model.set_columns({str(k): str(v) for k, v in columns.items()}, where=where)
        derived = spec.get("derived") or {}
        if not isinstance(derived, Mapping):
            raise ThermocalInputError(
                f"{where}: 'derived' must map names to expressions, e.g. "
                "heat_loss_coefficient: '1/Ria + 1/(Rie + Rea)'"
            )
        for dname, dspec in derived.items():
            if isinstance(dspec, Mapping):
                _check_keys(dspec, {"expression", "unit", "description"}, f"{where}: derived")
                expr, unit = dspec.get("expression"), str(dspec.get("unit", ""))
            else:
                expr, unit = dspec, ""
            if not isinstance(expr, (str, int, float)):
                raise ThermocalInputError(f"{where}: derived '{dname}' needs an expression")
            try:
                model.add_derived(str(dname), str(expr), unit=unit)
            except ThermocalInputError as exc:
                raise ThermocalInputError(f"{where}: {exc}") from None
        model.structure()  # validate now, with the file name in the messages
        return model

    @classmethod
    def from_yaml(cls, path: str | Path) -> RCModel:
        """Read a YAML model file (see ``docs/model-file.md``) with the safe reader
        :func:`thermocal.io.yamlfile.read_yaml` (duplicate keys, alias bombs, depth, size and
        encoding refused with the file and line)."""
        from thermocal.io.yamlfile import read_yaml

        return cls.from_dict(read_yaml(Path(path), what="model file"), source=str(path))

    def set_columns(self, columns: Mapping[str, str], *, where: str | None = None) -> RCModel:
        """Map the model's column names to data column names (``{model: data}``).

        The data is read with these renames (see :func:`thermocal.statespace.prepare_data`),
        so a model file written with ``Ph`` fits a table whose column is ``heating_kW``.
        """
        where = where or f"model '{self.name}'"
        seen: dict[str, str] = {}
        for name, data_name in columns.items():
            if data_name in seen:
                raise ThermocalInputError(
                    f"{where}: columns: '{seen[data_name]}' and '{name}' both map to data "
                    f"column '{data_name}'; map each model column to its own data column"
                )
            seen[data_name] = name
        self.columns = dict(columns)
        return self

    def check_columns(self, where: str | None = None) -> None:
        """Refuse ``columns:`` entries that name no column of the model."""
        where = where or f"{self.source} (model '{self.name}')"
        known = set(self.input_names) | set(self.output_names)
        unknown = [c for c in self.columns if c not in known]
        if unknown:
            raise ThermocalInputError(
                f"{where}: columns: {', '.join(map(repr, unknown))} is not a column of the "
                f"model (its columns: {', '.join(sorted(known))}); the keys are the model's "
                "names, the values the data's"
            )

    def with_periods(self, starts: Sequence[Mapping[str, float]]) -> RCModel:
        """Copy with one more set of initial states per period after the first.

        The likelihood split at long gaps (``input_gaps="split"``) restarts the state at each
        period; every state whose initial mean is an estimated parameter (``Ti0``) gets a new
        parameter per period (``Ti0_p2``, ``Ti0_p3``, ...) with the same unit and bounds, its
        start value taken from ``starts[p][state]`` when given (e.g. the first measured
        temperature of the period), else the declared one; fixed or constant initial means
        are reused.
        """
        self.structure()
        model = self.copy()
        model.period_initial_means = []
        for p, start in enumerate(starts, start=2):
            means: dict[str, str | float] = {}
            for state, spec in self._states.items():
                ref = spec.get("initial_mean")
                par = self.parameters.get(ref) if isinstance(ref, str) else None
                if par is None or par.fixed:
                    means[state] = ref
                    continue
                name = f"{ref}_p{p}"
                while name in model.parameters:
                    name += "_"
                value = par.value
                guess = start.get(state)
                if guess is not None and math.isfinite(guess):
                    span = par.upper - par.lower
                    margin = 1e-3 * span if math.isfinite(span) else 1e-3
                    value = min(max(float(guess), par.lower + margin), par.upper - margin)
                model.add_parameter(
                    name, value, unit=par.unit,
                    lower=par.lower if math.isfinite(par.lower) else None,
                    upper=par.upper if math.isfinite(par.upper) else None,
                    description=f"initial mean of {state} in period {p}",
                )  # fmt: skip
                means[state] = name
            model.period_initial_means.append(means)
        model._structure = None
        return model

    def to_dict(self) -> dict[str, Any]:
        """The model as a dictionary with the structure of the model file."""

        def clean(d: Mapping[str, Any]) -> dict[str, Any]:
            return {k: v for k, v in d.items() if v is not None}

        return {
            "name": self.name,
            "description": self.description,
            "states": {k: clean(v) for k, v in self._states.items()},
            "conductances": [clean(c) for c in self._conductances],
            "heat_inputs": [clean(h) for h in self._heat_inputs],
            "outputs": [clean(o) for o in self._outputs],
            "parameters": {k: p.to_dict() for k, p in self.parameters.items()},
            **(
                {"derived": {k: {"expression": e, "unit": u} for k, (e, u) in self.derived.items()}}
                if self.derived
                else {}
            ),
            **({"columns": dict(self.columns)} if self.columns else {}),
        }

    def copy(self) -> RCModel:
        """Deep copy (e.g. to change parameter settings without touching the original)."""
        return copy.deepcopy(self)

    def with_parameters(self, values: Mapping[str, float], *, fix: bool = False) -> RCModel:
        """Copy with new parameter values [declared units] (and optionally fixed)."""
        self.structure()  # validate (and resolve role-dependent default bounds) first
        model = self.copy()
        for name, val in values.items():
            if name not in model.parameters:
                raise ThermocalInputError(f"model '{self.name}': unknown parameter '{name}'")
            model.parameters[name].value = float(val)
            if fix:
                model.parameters[name].fixed = True
        model._structure = None
        return model

    # ------------------------------------------------------------------ names
    @property
    def state_names(self) -> list[str]:
        """State (node temperature) names, in state-vector order."""
        return list(self._states)

    @property
    def boundary_names(self) -> list[str]:
        """Boundary-temperature data columns [C], in order of first appearance."""
        names: list[str] = []
        for c in self._conductances:
            for node in c["between"]:
                if node not in self._states and node not in names:
                    names.append(node)
        return names

    @property
    def heat_input_names(self) -> list[str]:
        """Heat-input data columns, in order of first appearance."""
        names: list[str] = []
        for h in self._heat_inputs:
            if h["column"] not in names:
                names.append(h["column"])
        return names

    @property
    def input_names(self) -> list[str]:
        """Input vector order: boundary temperatures first, then heat inputs."""
        return self.boundary_names + self.heat_input_names

    @property
    def output_names(self) -> list[str]:
        """Observed data columns, in output-vector order."""
        return [o["column"] for o in self._outputs]

    @property
    def parameter_names(self) -> list[str]:
        """All parameter names, in declaration order."""
        return list(self.parameters)

    @property
    def free_parameter_names(self) -> list[str]:
        """Names of the parameters that are estimated."""
        return [p.name for p in self.parameters.values() if not p.fixed]

    @property
    def n_free(self) -> int:
        """Number of estimated parameters."""
        return len(self.free_parameter_names)

    # ------------------------------------------------------------------ compilation
    def structure(self) -> Structure:
        """Validate the declaration and compile it into index arrays for the kernels."""
        if self._structure is None:
            self._structure = _compile(self)
        return self._structure

    def values_si(self, params: Mapping[str, float] | None = None) -> np.ndarray:
        """Vector of all parameter values in SI followed by the model's constants."""
        st = self.structure()
        values = np.empty(len(self.parameters) + st.constants.size)
        for i, p in enumerate(self.parameters.values()):
            val = p.value if params is None or p.name not in params else float(params[p.name])
            values[i] = val * p.si_factor
        values[len(self.parameters) :] = st.constants
        return values

    def transform_arrays(self) -> tuple:
        """(free_idx, kind, lower, upper, si_factor, base_values) for the kernels."""
        names = self.parameter_names
        free = [self.parameters[n] for n in self.free_parameter_names]
        st = self.structure()
        si = np.array([p.si_factor for p in self.parameters.values()] + [1.0] * st.constants.size)
        return (
            np.array([names.index(p.name) for p in free], dtype=np.int64),
            np.array([p.transform for p in free], dtype=np.int64),
            np.array([p.lower for p in free], dtype=float),
            np.array([p.upper for p in free], dtype=float),
            si,
            self.values_si(),
        )

    def theta0(self) -> np.ndarray:
        """Unconstrained start vector from the declared values of the free parameters."""
        self.structure()  # resolves default bounds that depend on a parameter's role
        return np.array(
            [
                self.parameters[n].to_unconstrained(self.parameters[n].value)
                for n in self.free_parameter_names
            ]
        )

    def system(self, params: Mapping[str, float] | None = None):
        """Eigen-form system used by the kernels (see :func:`kernels.system_from_values`)."""
        st = self.structure()
        return kernels.system_from_values(self.values_si(params), *st.arrays[:19], st.n_inputs)

    def period_initial_means_si(self, params: Mapping[str, float] | None = None) -> np.ndarray:
        """Initial means [C] of the periods after the first, shape (periods - 1, states)."""
        st = self.structure()
        return kernels.period_initial_means(self.values_si(params), st.arrays[19], st.n_states)

    def continuous_matrices(
        self, params: Mapping[str, float] | None = None
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Continuous-time matrices ``(A, B, C, D)`` in SI units (time in seconds).

        Parameters
        ----------
        params : mapping, optional
            Parameter values [declared units] overriding the declared ones.

        Returns
        -------
        A : ndarray (n_states, n_states) [1/s]
        B : ndarray (n_states, n_inputs) [K/(s C)] for boundary temperatures, [K/(s W)] (times
            the column-unit factor) for heat inputs
        C : ndarray (n_outputs, n_states) [-]
        D : ndarray (n_outputs, n_inputs) [-], zero
        """
        st = self.structure()
        cap, G, B_raw, _ = kernels.build_network(
            self.values_si(params), *st.arrays[:15], st.arrays[18], st.n_inputs
        )
        A = G / cap[:, None]
        B = B_raw / cap[:, None]
        D = np.zeros((st.C.shape[0], st.n_inputs))
        return A, B, st.C.copy(), D

    def heat_loss_state(self) -> str | None:
        """The state whose heat loss coefficient the model implies: the state observed alone
        (coefficient 1) by the first such output, when the network connects it to a boundary
        temperature; None otherwise."""
        st = self.structure()
        if not self.boundary_names:
            return None
        for r in range(st.C.shape[0]):
            nz = np.flatnonzero(st.C[r])
            if nz.size == 1 and st.C[r, nz[0]] == 1.0:
                return self.state_names[nz[0]]
        return None

    def heat_loss_coefficient(
        self, params: Mapping[str, float] | None = None, *, state: str | None = None
    ) -> float:
        """Steady-state heat loss coefficient [W/K] of a state to all boundary temperatures.

        The heat flow out of ``state`` per kelvin when it is held 1 K above every boundary
        temperature and the other states float to their steady state without heat input:
        ``H = -(G_ss + G_sf x_f)`` with ``G_ff x_f = -G_fs`` (``G`` the conductance matrix of the
        network, ``f`` the other states). For the Bacher & Madsen models this is
        ``1/Ria + 1/(Rie + Rea)`` (Bacher & Madsen 2011); the heat that a heater state or the
        thermal mass stores is not a loss.

        Parameters
        ----------
        params : mapping, optional
            Parameter values [declared units] (default: the declared values).
        state : str, optional
            Default: :meth:`heat_loss_state`.

        Returns
        -------
        float
            [W/K]; NaN when the network has no steady state.
        """
        state = state or self.heat_loss_state()
        if state is None:
            raise ThermocalInputError(
                f"model '{self.name}': no heat loss coefficient: no output observes a single "
                "state connected to a boundary temperature"
            )
        st = self.structure()
        _, G, _, _ = kernels.build_network(
            self.values_si(params), *st.arrays[:15], st.arrays[18], st.n_inputs
        )
        return float(kernels.heat_loss_from_network(G, self.state_names.index(state)))

    def diffusion_matrix(self, params: Mapping[str, float] | None = None) -> np.ndarray:
        """Diagonal diffusion matrix ``Sigma`` [K/sqrt(s)] of ``dx = f dt + Sigma dw``."""
        st = self.structure()
        _, _, _, sigma = kernels.build_network(
            self.values_si(params), *st.arrays[:15], st.arrays[18], st.n_inputs
        )
        return np.diag(sigma)

    # ------------------------------------------------------------------ estimation & simulation
    def fit(
        self,
        data,
        *,
        hold: str = "zoh",
        n_starts: int | None = None,
        seed: int | None = None,
        time_column: str | None = None,
        time_unit: str = "s",
        **opts,
    ):
        """Maximum-likelihood estimation; returns :class:`~thermocal.statespace.FitResults`.

        See :func:`thermocal.statespace.estimation.fit` for the options.
        """
        from thermocal.statespace.estimation import fit

        return fit(
            self,
            data,
            hold=hold,
            n_starts=n_starts,
            seed=seed,
            time_column=time_column,
            time_unit=time_unit,
            **opts,
        )

    def simulate(
        self,
        data,
        params: Mapping[str, float] | None = None,
        *,
        hold: str = "zoh",
        time_column: str | None = None,
        time_unit: str = "s",
        initial_state: Mapping[str, float] | None = None,
        interval_means: bool = False,
    ):
        """Deterministic (noise-free) state and output trajectories from the initial-state mean.

        ``initial_state`` ({state: temperature [C]}) replaces the declared initial means of the
        states it names, e.g. to simulate a validation period that starts later than the fit.
        ``interval_means``: each value is the mean over the interval its time label starts
        [C], as a logger that averages records it (:func:`thermocal.statespace.kalman.
        interval_means_of`), instead of the value at the label.
        Returns a DataFrame on the data's index with one column per state and per output
        (outputs named after their data column).
        """
        from thermocal.statespace.estimation import simulate

        return simulate(
            self,
            data,
            params,
            hold=hold,
            time_column=time_column,
            time_unit=time_unit,
            initial_state=initial_state,
            interval_means=interval_means,
        )

    def evaluate(
        self,
        data,
        params: Mapping[str, float] | None = None,
        *,
        hold: str = "zoh",
        time_column: str | None = None,
        time_unit: str = "s",
    ):
        """:class:`FitResults` at given parameters [declared units] without optimisation."""
        from thermocal.statespace.estimation import evaluate

        return evaluate(self, data, params, hold=hold, time_column=time_column, time_unit=time_unit)

    def loglike(
        self,
        data,
        params: Mapping[str, float] | None = None,
        *,
        hold: str = "zoh",
        time_column: str | None = None,
        time_unit: str = "s",
    ) -> float:
        """Log-likelihood of the outputs in ``data`` at ``params`` [declared units]."""
        from thermocal.statespace.estimation import loglike

        return loglike(self, data, params, hold=hold, time_column=time_column, time_unit=time_unit)

    def __repr__(self) -> str:
        return (
            f"RCModel(name={self.name!r}, states={self.state_names}, inputs={self.input_names}, "
            f"outputs={self.output_names}, free={self.free_parameter_names})"
        )


def _parse_prior(p: Parameter, prior: Any, model_name: str) -> tuple:
    where = f"model '{model_name}': parameter '{p.name}': prior"
    if prior == "uniform" or (isinstance(prior, Mapping) and "uniform" in prior):
        if not (math.isfinite(p.lower) and math.isfinite(p.upper)):
            raise ThermocalInputError(f"{where} 'uniform' needs both bounds (lower and upper)")
        return ("uniform", p.lower, p.upper)
    if isinstance(prior, Mapping) and len(prior) == 1:
        kind, args = next(iter(prior.items()))
        if kind in ("normal", "lognormal") and isinstance(args, Sequence) and len(args) == 2:
            a, b = (_as_float(v, where) for v in args)
            if b <= 0 or (kind == "lognormal" and a <= 0):
                raise ThermocalInputError(
                    f"{where}: {kind} needs a positive "
                    f"{'median and ' if kind == 'lognormal' else ''}standard deviation"
                )
            return (kind, a, b)
    raise ThermocalInputError(
        f"{where} {prior!r}: write {{normal: [mean, std]}}, {{lognormal: [median, std_log]}} or "
        "uniform (values in the parameter's unit)"
    )


_FUNCTIONS = {"sqrt": math.sqrt, "exp": math.exp, "log": math.log, "abs": abs}


def _expression_tree(expression: str, what: str):
    import ast

    try:
        tree = ast.parse(expression, mode="eval")
    except SyntaxError:
        raise ThermocalInputError(
            f"{what}: {expression!r} is not an arithmetic expression"
        ) from None
    allowed = (
        ast.Expression, ast.BinOp, ast.UnaryOp, ast.Constant, ast.Name, ast.Call, ast.Load,
        ast.Add, ast.Sub, ast.Mult, ast.Div, ast.Pow, ast.USub, ast.UAdd,
    )  # fmt: skip
    for node in ast.walk(tree):
        if not isinstance(node, allowed):
            raise ThermocalInputError(
                f"{what}: {expression!r}: only numbers, parameter names, + - * / **, "
                f"parentheses and {', '.join(_FUNCTIONS)} are allowed"
            )
        if isinstance(node, ast.Call) and (
            not isinstance(node.func, ast.Name) or node.func.id not in _FUNCTIONS or node.keywords
        ):
            raise ThermocalInputError(
                f"{what}: {expression!r}: functions allowed: {', '.join(_FUNCTIONS)}"
            )
    return tree


def _expression_names(expression: str, what: str) -> set[str]:
    import ast

    tree = _expression_tree(expression, what)
    calls = {id(n.func) for n in ast.walk(tree) if isinstance(n, ast.Call)}
    return {n.id for n in ast.walk(tree) if isinstance(n, ast.Name) and id(n) not in calls}


def evaluate_expression(expression: str, values: Mapping[str, float]) -> float:
    """Value of a derived-quantity expression (see :meth:`RCModel.add_derived`)."""
    import ast

    tree = _expression_tree(expression, "derived quantity")
    ops = {
        ast.Add: lambda a, b: a + b, ast.Sub: lambda a, b: a - b, ast.Mult: lambda a, b: a * b,
        ast.Div: lambda a, b: a / b if b != 0 else math.inf, ast.Pow: lambda a, b: a**b,
    }  # fmt: skip

    def ev(node) -> float:
        if isinstance(node, ast.Expression):
            return ev(node.body)
        if isinstance(node, ast.Constant):
            return float(node.value)
        if isinstance(node, ast.Name):
            return float(values[node.id])
        if isinstance(node, ast.UnaryOp):
            v = ev(node.operand)
            return -v if isinstance(node.op, ast.USub) else v
        if isinstance(node, ast.BinOp):
            return float(ops[type(node.op)](ev(node.left), ev(node.right)))
        try:
            return float(_FUNCTIONS[node.func.id](*[ev(a) for a in node.args]))
        except (ValueError, OverflowError):
            return math.nan

    return ev(tree)


def _check_keys(spec: Any, allowed: set[str], where: str) -> None:
    if not isinstance(spec, Mapping):
        raise ThermocalInputError(f"{where} must be a mapping")
    unknown = set(spec) - allowed
    if unknown:
        raise ThermocalInputError(
            f"{where}: unknown key(s) {sorted(unknown)}; allowed: {sorted(allowed)}"
        )


class _Compiler:
    def __init__(self, model: RCModel) -> None:
        self.model = model
        self.where = f"{model.source} (model '{model.name}')"
        self.param_index = {name: i for i, name in enumerate(model.parameters)}
        self.constants: list[float] = []
        self.roles: dict[str, set[str]] = {}

    def ref(self, value: Any, role: str, what: str) -> int:
        """Index of a parameter name or literal constant in the value vector."""
        if value is None:
            raise ThermocalInputError(f"{self.where}: {what} is missing ({role})")
        if isinstance(value, bool):
            raise ThermocalInputError(f"{self.where}: {what} must be a parameter name or number")
        if isinstance(value, str):
            if value not in self.param_index:
                try:
                    value = float(value)
                except ValueError:
                    raise ThermocalInputError(
                        f"{self.where}: {what} refers to '{value}', which is neither a declared "
                        f"parameter nor a number; declare it under 'parameters:' "
                        f"(declared: {', '.join(self.param_index) or 'none'})"
                    ) from None
            else:
                self.roles.setdefault(value, set()).add(role)
                return self.param_index[value]
        number = _as_float(value, f"{self.where}: {what}")
        if role in _POSITIVE_ROLES and not number > 0:
            raise ThermocalInputError(f"{self.where}: {what} = {number} must be positive")
        if role == "initial mean" and number > KELVIN_INITIAL_MEAN:
            raise ThermocalInputError(
                f"{self.where}: {what} = {number:g} looks like kelvin; states are in degrees C: "
                f"write {number - 273.15:.6g}"
            )
        if role in _NONNEGATIVE_ROLES and not number >= 0:
            raise ThermocalInputError(f"{self.where}: {what} = {number} must not be negative")
        self.constants.append(number)
        return len(self.model.parameters) + len(self.constants) - 1


def _compile(model: RCModel) -> Structure:
    cp = _Compiler(model)
    where = cp.where
    states = model.state_names
    if not states:
        raise ThermocalInputError(f"{where}: the model declares no states")
    sidx = {s: i for i, s in enumerate(states)}
    boundary = model.boundary_names
    heat_cols = model.heat_input_names
    n_b = len(boundary)

    cap_idx = []
    noise_idx = []
    x0_idx = []
    p0_idx = []
    for s in states:
        spec = model._states[s]
        if spec.get("capacity") is None:
            raise ThermocalInputError(
                f"{where}: state '{s}' has no capacity; give it 'capacity: <parameter>' "
                "(a heat capacity in J/K, kJ/K, MJ/K or kWh/K)"
            )
        cap_idx.append(cp.ref(spec["capacity"], "capacity", f"capacity of state '{s}'"))
        noise = spec.get("noise")
        noise_idx.append(-1 if noise is None else cp.ref(noise, "noise", f"noise of state '{s}'"))
        if spec.get("initial_mean") is None:
            raise ThermocalInputError(
                f"{where}: state '{s}' has no 'initial_mean' (its temperature at the first sample "
                "[C], a parameter or a number)"
            )
        x0_idx.append(cp.ref(spec["initial_mean"], "initial mean", f"initial_mean of '{s}'"))
        std = spec.get("initial_std")
        p0_idx.append(
            cp.ref(
                DEFAULT_INITIAL_STD if std is None else std, "initial std", f"initial_std of '{s}'"
            )
        )

    seg_x0_idx = []
    for p, means in enumerate(model.period_initial_means, start=2):
        for s in states:
            seg_x0_idx.append(
                cp.ref(means.get(s), "initial mean", f"initial mean of '{s}' in period {p}")
            )

    edge_a, edge_b, link_ptr, link_idx, link_res, link_factor = [], [], [0], [], [], []
    for i, c in enumerate(model._conductances):
        a, b = c["between"]
        what = f"conductances[{i}] ({a}-{b})"
        if a == b:
            raise ThermocalInputError(f"{where}: {what} connects '{a}' to itself")
        if a not in sidx and b not in sidx:
            raise ThermocalInputError(
                f"{where}: {what}: neither '{a}' nor '{b}' is a state "
                f"(states: {', '.join(states)}); "
                "at least one end must be a state, the other may be a boundary-temperature column"
            )
        if a not in sidx:
            a, b = b, a
        edge_a.append(sidx[a])
        edge_b.append(sidx[b] if b in sidx else -(boundary.index(b) + 1))
        has_g, has_r = c.get("conductance") is not None, c.get("resistance") is not None
        if has_g == has_r:
            raise ThermocalInputError(
                f"{where}: {what} needs exactly one of 'conductance' [W/K] or 'resistance' [K/W]"
            )
        role = "conductance" if has_g else "resistance"
        links = c[role]
        if isinstance(links, str) or not isinstance(links, Sequence):
            links = [links]
        if not links:
            raise ThermocalInputError(f"{where}: {what}: empty {role} list")
        for link in links:
            factor = 1.0
            if isinstance(link, str):
                match = _FACTOR_PATTERN.match(link)
                if match:
                    factor = _as_float(match.group(1), f"{where}: factor in '{link}' of {what}")
                    if not factor > 0:
                        raise ThermocalInputError(f"{where}: factor in '{link}' must be positive")
                    link = match.group(2)
            link_idx.append(cp.ref(link, role, f"{role} of {what}"))
            link_res.append(1 if role == "resistance" else 0)
            link_factor.append(factor)
        link_ptr.append(len(link_idx))

    heat_state, heat_input, heat_factor, heat_scale = [], [], [], []
    frac_const, frac_ptr, frac_idx, frac_sign = [], [0], [], []
    from thermocal.statespace.units import HEAT_COLUMN_UNITS

    for i, h in enumerate(model._heat_inputs):
        col = h["column"]
        what = f"heat_inputs[{i}] (column '{col}')"
        unit = h.get("unit") or "W"
        if unit not in HEAT_COLUMN_UNITS:
            raise ThermocalInputError(
                f"{where}: {what}: unknown column unit '{unit}'; use one of "
                f"{', '.join(HEAT_COLUMN_UNITS)}"
            )
        if col in sidx:
            raise ThermocalInputError(f"{where}: {what}: '{col}' is a state, not a data column")
        scale = h.get("scale")
        scale_idx = -1 if scale is None else cp.ref(scale, "scale", f"scale of {what}")
        into = h["into"]
        if isinstance(into, str):
            into = {into: 1.0}
        if not isinstance(into, Mapping) or not into:
            raise ThermocalInputError(
                f"{where}: {what}: 'into' must be a state or {{state: fraction}}"
            )
        rest_states = [s for s, f in into.items() if f == "rest"]
        if len(rest_states) > 1:
            raise ThermocalInputError(f"{where}: {what}: only one fraction may be 'rest'")
        constant_total = sum(
            _as_float(f, f"{where}: fraction of {what} into '{s}'")
            for s, f in into.items()
            if not (isinstance(f, str) and (f == "rest" or f in cp.param_index))
        )
        if constant_total > 1.0 + 1e-9:
            raise ThermocalInputError(
                f"{where}: {what}: the fractions add up to {constant_total:g} > 1 (more heat "
                "than the column holds); make them sum to at most 1"
            )
        for s, f in into.items():
            if s not in sidx:
                raise ThermocalInputError(
                    f"{where}: {what} goes into '{s}', which is not a state "
                    f"(states: {', '.join(states)})"
                )
            heat_state.append(sidx[s])
            heat_input.append(n_b + heat_cols.index(col))
            heat_factor.append(HEAT_COLUMN_UNITS[unit])
            heat_scale.append(scale_idx)
            if f == "rest":
                const = 1.0
                for s2, f2 in into.items():
                    if s2 == s:
                        continue
                    if isinstance(f2, str) and f2 in cp.param_index:
                        frac_idx.append(cp.ref(f2, "fraction", f"fraction of {what} into '{s2}'"))
                        frac_sign.append(-1.0)
                    else:
                        const -= _as_float(f2, f"{where}: fraction of {what} into '{s2}'")
                frac_const.append(const)
            elif isinstance(f, str) and f in cp.param_index:
                frac_idx.append(cp.ref(f, "fraction", f"fraction of {what} into '{s}'"))
                frac_sign.append(1.0)
                frac_const.append(0.0)
            else:
                fraction = _as_float(f, f"{where}: fraction of {what} into '{s}'")
                if not 0.0 <= fraction <= 1.0:
                    raise ThermocalInputError(
                        f"{where}: {what}: fraction into '{s}' is {fraction:g}; a fraction "
                        "must lie in [0, 1]"
                    )
                frac_const.append(fraction)
            frac_ptr.append(len(frac_idx))

    if not model._outputs:
        raise ThermocalInputError(f"{where}: the model declares no outputs (observed columns)")
    C = np.zeros((len(model._outputs), len(states)))
    meas_idx = []
    for r, o in enumerate(model._outputs):
        what = f"outputs[{r}] (column '{o['column']}')"
        combo = o.get("states")
        if o.get("state") is not None:
            if combo is not None:
                raise ThermocalInputError(f"{where}: {what}: give 'state' or 'states', not both")
            combo = {o["state"]: 1.0}
        if not combo:
            raise ThermocalInputError(f"{where}: {what} needs 'state: <state>' (or 'states')")
        for s, coef in combo.items():
            if s not in sidx:
                raise ThermocalInputError(
                    f"{where}: {what} observes '{s}', which is not a state "
                    f"(states: {', '.join(states)})"
                )
            C[r, sidx[s]] += _as_float(coef, f"{where}: {what} coefficient of '{s}'")
        meas_idx.append(cp.ref(o["noise"], "measurement noise", f"noise of {what}"))

    _check_parameters(model, cp.roles, where)
    # every state must lose heat somewhere or be connected: warn via error only if isolated
    connected = {i: False for i in range(len(states))}
    for a, b in zip(edge_a, edge_b, strict=True):
        connected[a] = True
        if b >= 0:
            connected[b] = True
    for i, ok in connected.items():
        if not ok and len(states) > 1:
            raise ThermocalInputError(
                f"{where}: state '{states[i]}' has no conductance to any other node; connect it"
            )

    i64 = lambda x: np.asarray(x, dtype=np.int64)  # noqa: E731
    f64 = lambda x: np.asarray(x, dtype=np.float64)  # noqa: E731
    arrays = (
        i64(cap_idx),
        i64(edge_a),
        i64(edge_b),
        i64(link_ptr),
        i64(link_idx),
        i64(link_res),
        i64(heat_state),
        i64(heat_input),
        f64(heat_factor),
        i64(heat_scale),
        f64(frac_const),
        i64(frac_ptr),
        i64(frac_idx),
        f64(frac_sign),
        i64(noise_idx),
        i64(meas_idx),
        i64(x0_idx),
        i64(p0_idx),
        f64(link_factor),
        i64(seg_x0_idx),
    )
    return Structure(
        arrays=arrays,
        C=C,
        n_states=len(states),
        n_inputs=n_b + len(heat_cols),
        constants=np.asarray(cp.constants, dtype=float),
        roles=cp.roles,
    )


def _check_parameters(model: RCModel, roles: dict[str, set[str]], where: str) -> None:
    for name, p in model.parameters.items():
        pwhere = f"{where}: parameter '{name}'"
        if not p.lower < p.upper:
            raise ThermocalInputError(
                f"{pwhere}: lower bound {p.lower} must be below upper bound {p.upper}"
            )
        if not math.isfinite(p.value):
            raise ThermocalInputError(f"{pwhere}: value must be a finite number")
        if not p.fixed and not (p.lower < p.value < p.upper):
            raise ThermocalInputError(
                f"{pwhere}: initial value {p.value} {p.unit} is outside its bounds "
                f"[{p.lower}, {p.upper}] (it must lie strictly inside); "
                "change the value or the bounds"
            )
        if p.fixed and not (p.lower <= p.value <= p.upper):
            raise ThermocalInputError(
                f"{pwhere}: fixed value {p.value} {p.unit} is outside its bounds "
                f"[{p.lower}, {p.upper}]; change the value or the bounds"
            )
        used = roles.get(name, set())
        if not used and not p.fixed:
            raise ThermocalInputError(
                f"{pwhere} is estimated but not used anywhere in the model; use it or remove it"
            )
        kind = UNIT_KIND[p.unit]
        if p.auto_lower and used & (_POSITIVE_ROLES | _NONNEGATIVE_ROLES):
            p.lower = 0.0
        for role in used:
            if kind not in _ROLE_KINDS[role]:
                raise ThermocalInputError(
                    f"{pwhere} is used as {role} but has unit '{p.unit}' ({kind}); "
                    f"give it a unit of kind {sorted(_ROLE_KINDS[role])}"
                )
            if role in _POSITIVE_ROLES:
                if not p.value > 0:
                    raise ThermocalInputError(f"{pwhere} ({role}) must be positive, got {p.value}")
                if not p.fixed and p.lower < 0:
                    raise ThermocalInputError(
                        f"{pwhere} ({role}) has a negative lower bound {p.lower}; use lower >= 0"
                    )
            if role in _NONNEGATIVE_ROLES:
                if not p.value >= 0:
                    raise ThermocalInputError(f"{pwhere} ({role}) must not be negative")
                if not p.fixed and p.lower < 0:
                    raise ThermocalInputError(
                        f"{pwhere} ({role}) has a negative lower bound {p.lower}; use lower >= 0"
                    )
            if role == "fraction" and not (0.0 <= p.lower and p.upper <= 1.0 or p.fixed):
                raise ThermocalInputError(
                    f"{pwhere} is a fraction with bounds [{p.lower}, {p.upper}]; give it "
                    "'lower: 0' and 'upper: 1' (or narrower)"
                )
            if role == "initial mean" and p.unit == "K":
                raise ThermocalInputError(
                    f"{pwhere} is an initial mean (a temperature) in unit 'K'; states are in "
                    f"degrees C: write unit: C and value {p.value - 273.15:.6g} "
                    f"(= {p.value:g} K - 273.15)"
                    + (", and convert the bounds" if math.isfinite(p.lower + p.upper) else "")
                    if p.value > KELVIN_INITIAL_MEAN
                    else f"{pwhere} is an initial mean (a temperature) in unit 'K'; states are "
                    "in degrees C: write unit: C (K is for standard deviations)"
                )
            if role == "initial mean" and p.value > KELVIN_INITIAL_MEAN:
                raise ThermocalInputError(
                    f"{pwhere}: initial mean {p.value:g} {p.unit} looks like kelvin; states are "
                    f"in degrees C: write {p.value - 273.15:.6g}"
                )
            if role == "fraction" and not 0.0 <= p.value <= 1.0:
                raise ThermocalInputError(f"{pwhere} is a fraction and must lie in [0, 1]")
            if role == "measurement noise" and not p.value > 0:
                raise ThermocalInputError(
                    f"{pwhere}: a measurement standard deviation must be positive"
                )
