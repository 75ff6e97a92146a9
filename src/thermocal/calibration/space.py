"""Parameter spaces of an envelope-calibration campaign.

A :class:`ParameterSpace` holds the named model parameters that a campaign varies, their nominal
values, the sampling range (a relative half-width around the nominal value) and the physical
limits that every sampled value is clipped to.

Clipping policy (as in the paper, section "Parameter Sampling"): the sampler draws values
uniformly in the *unclipped* range ``nominal * (1 -+ relative_range)``; every value outside the
physical limits is then set to the limit and counted (:meth:`ParameterSpace.clip`).  A range of
+-10000 % on a solar heat gain coefficient therefore puts most samples on its limits 0.01 x nominal
and 1; the counts say how many.  The physical limits are:

* every property is strictly positive: lower limit ``floor_fraction * nominal`` (default 1 % of the
  nominal value; the paper's Table 1 has a thickness of 0.0001 m from a nominal 0.0100 m, i.e. 1 %);
* fractions (``*/shgc``) are at most 1, a window U-value at most 10 W/(m2 K);
* layer properties stay inside the building model's plausible ranges
  (:data:`thermocal.multizone.model.PLAUSIBLE`: e.g. density 5 to 25,000 kg/m3), so that the
  model never refuses a sample (:func:`physical_limits` is the one source of these limits);
* no upper limit otherwise.

Parameter names are those of :meth:`thermocal.multizone.Building.parameters`:
``material/<name>/{conductivity,density,specific_heat,thickness}``, ``material/<name>/resistance``,
``window/<name>/{u_value,shgc}``, ``zone/<name>/infiltration_ach`` and ``infiltration/<group>/ach``.

References
----------
.. [1] "Calibration of envelope parameters using control-based heat balance identification and
   uncertainty analysis" (:data:`thermocal.identification.REFERENCE`): envelope calibration with
   cheap temperature sensors, PID heat identification, SVR meta-model and optimisation.
"""

from __future__ import annotations

import difflib
import fnmatch
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.multizone.parameters import PARAMETER_UNITS, parameter_kind, parameter_unit

__all__ = [
    "DEFAULT_RELATIVE_RANGE",
    "FLOOR_FRACTION",
    "UNITS",
    "ParameterSpace",
    "parameter_kind",
    "parameter_unit",
    "physical_limits",
]

#: Default relative half-width of the sampling range (+-75 %, the paper's default) [-].
DEFAULT_RELATIVE_RANGE = 0.75
#: Lower physical limit of every property as a fraction of its nominal value [-].
FLOOR_FRACTION = 0.01

#: Unit of each parameter kind (the last part of the name), for tables.
UNITS: dict[str, str] = PARAMETER_UNITS

#: Kinds that are fractions, limited to (0, 1].
FRACTION_KINDS = frozenset({"shgc"})
#: Relative margin kept inside the model's hard limits [-].
LIMIT_MARGIN = 1e-9
#: upper limits the building model accepts, by kind (a window U-value above 10 W/(m2 K) is
#: rejected by :class:`thermocal.multizone.WindowType`)
UPPER_LIMITS = {"u_value": 10.0}


def physical_limits(name: str, nominal: float, floor_fraction: float = FLOOR_FRACTION
                    ) -> tuple[float, float]:
    """Physical limits of a parameter: the values the building model accepts.

    One source of limits for sampling, meta-models and optimisation: the building model's own
    plausible ranges of layer properties (:data:`thermocal.multizone.model.PLAUSIBLE`, e.g. a
    density of at least 5 kg/m3), its upper limits (window U-value <= 10 W/(m2 K), fractions
    <= 1), and everywhere at least ``floor_fraction * nominal`` (strictly positive), so that
    no sample the campaign draws is refused by the model it is meant for.

    Parameters
    ----------
    name : str
        Parameter name, e.g. ``"material/Insulation/density"`` [-].
    nominal : float
        Nominal value [unit of the parameter].
    floor_fraction : float
        Lower limit as a fraction of the nominal value [-].

    Returns
    -------
    (float, float)
        Lower and upper limit [unit of the parameter]; the upper limit may be ``inf``.
    """
    from thermocal.multizone.model import PLAUSIBLE

    kind = parameter_kind(name)
    lower, upper = floor_fraction * float(nominal), np.inf
    if kind in FRACTION_KINDS:
        upper = 1.0
    upper = min(upper, UPPER_LIMITS.get(kind, np.inf))
    if name.startswith("material/") and kind in PLAUSIBLE:
        model_lower, model_upper = PLAUSIBLE[kind][:2]
        lower, upper = max(lower, model_lower * (1.0 + LIMIT_MARGIN)), min(upper, model_upper)
    # a hair inside the model's own upper limits: a value computed in logarithms and sitting on
    # the limit (a posterior median, an optimum) comes back a rounding error above it, which the
    # model refuses (a window U-value of 10.000000000000002 W/(m2 K))
    return float(lower), float(upper * (1.0 - LIMIT_MARGIN))


def _pattern_candidates(names: Sequence[str]) -> list[str]:
    """Names and typical patterns a mistyped pattern may have meant."""
    cands = set(names)
    for n in names:
        parts = n.split("/")
        cands.add(f"*/{parts[-1]}")
        cands.add(f"{parts[0]}/*")
        if len(parts) == 3:
            cands.add(f"{parts[0]}/*/{parts[2]}")
            cands.add(f"{parts[0]}/{parts[1]}/*")
    return sorted(cands)


def _no_match_error(pattern: str, what: str, names: Sequence[str]) -> ThermocalInputError:
    close = difflib.get_close_matches(pattern, _pattern_candidates(names), n=3, cutoff=0.5)
    hint = f"; did you mean {', '.join(repr(c) for c in close)}?" if close else ""
    example = ", ".join(repr(n) for n in list(names)[:3])
    return ThermocalInputError(
        f"parameters.{what}: pattern {pattern!r} matches no model parameter{hint} "
        f"(names look like {example}; correct or remove the pattern)"
    )


def _matches(name: str, pattern: str) -> bool:
    return fnmatch.fnmatchcase(name, pattern)


@dataclass(frozen=True)
class ParameterSpace:
    """The parameters a campaign varies, with sampling ranges and physical limits.

    Build it with :meth:`from_parameters`; all arrays follow the order of :attr:`names`.

    Attributes
    ----------
    names : tuple of str
        Parameter names [-].
    nominal : ndarray
        Nominal values [unit of each parameter, see :attr:`units`].
    relative_range : ndarray
        Relative half-width of the sampling range [-] (0.75 = +-75 %).
    range_lower, range_upper : ndarray
        Unclipped sampling range ``nominal * (1 -+ relative_range)`` [unit of each parameter].
    limit_lower, limit_upper : ndarray
        Physical limits [unit of each parameter]: ``floor_fraction * nominal`` and 1 for fractions,
        ``inf`` otherwise.
    skipped : dict
        Selected parameters left out, with the reason (a zero nominal value has no relative range).
    """

    names: tuple[str, ...]
    nominal: np.ndarray
    relative_range: np.ndarray
    range_lower: np.ndarray
    range_upper: np.ndarray
    limit_lower: np.ndarray
    limit_upper: np.ndarray
    floor_fraction: float = FLOOR_FRACTION
    skipped: dict[str, str] = field(default_factory=dict)

    # ------------------------------------------------------------------------------------------
    @classmethod
    def from_parameters(
        cls,
        parameters: Mapping[str, float],
        *,
        include: Iterable[str] | None = None,
        exclude: Iterable[str] = (),
        default_range: float = DEFAULT_RELATIVE_RANGE,
        ranges: Mapping[str, float] | None = None,
        floor_fraction: float = FLOOR_FRACTION,
        unused: Mapping[str, str] | None = None,
        limits: Mapping[str, tuple[float, float]] | None = None,
    ) -> ParameterSpace:
        """Select parameters by glob patterns and give them ranges.

        Parameters
        ----------
        parameters : mapping of str to float
            Nominal values by name, as returned by ``Building.parameters()`` [unit of each
            parameter].
        include : iterable of str, optional
            ``fnmatch`` patterns of the names to vary (default: all), e.g. ``"material/*"`` [-].
        exclude : iterable of str
            Patterns of names to leave at their nominal value, applied after ``include`` [-].
        default_range : float
            Relative half-width of the uniform sampling range [-] (0.75 = +-75 %).
        ranges : mapping of str to float, optional
            Per-pattern relative half-widths overriding ``default_range`` [-], e.g.
            ``{"*/shgc": 100.0, "*/thickness": 10.0}`` (+-10000 % and +-1000 %, the paper's).
            Patterns matching the same name must give it the same half-width (else refused:
            the order of the keys would decide silently).
        floor_fraction : float
            Lower physical limit of every property as a fraction of its nominal value [-].
        unused : mapping of str to str, optional
            Names that change nothing in the model, with the reason
            (:func:`thermocal.multizone.elements.unused_parameters`): selected, they are left
            out and listed in ``skipped``.
        limits : mapping of str to (float, float), optional
            Limits the model sets on some parameters beyond :func:`physical_limits` (e.g. the
            element parameters' from their layers,
            :func:`thermocal.multizone.elements.element_limits`) [unit of each parameter].

        Returns
        -------
        ParameterSpace

        Raises
        ------
        ThermocalInputError
            A pattern matching no parameter (with a "did you mean"), two ``ranges`` patterns
            giving one parameter different half-widths, a negative or non-finite range, a
            negative or non-finite nominal value, or an empty selection.
        """
        if not isinstance(parameters, Mapping) or not parameters:
            raise ThermocalInputError(
                "parameters: the model has no named parameters to calibrate "
                "(expected a mapping name -> nominal value from Building.parameters())"
            )
        all_names = [str(n) for n in parameters]
        include = ["*"] if include is None else [str(p) for p in include]
        exclude = [str(p) for p in exclude]
        ranges = {} if ranges is None else {str(k): v for k, v in ranges.items()}
        _check_range("parameters.default_range", default_range)
        for pattern, value in ranges.items():
            _check_range(f"parameters.ranges[{pattern!r}]", value)
        if not 0.0 < float(floor_fraction) < 1.0:
            raise ThermocalInputError(
                f"floor_fraction must be in (0, 1), got {floor_fraction!r}"
            )

        for pattern in include:
            if not any(_matches(n, pattern) for n in all_names):
                raise _no_match_error(pattern, "include", all_names)
        selected = [n for n in all_names if any(_matches(n, p) for p in include)]
        for pattern in exclude:
            if not any(_matches(n, pattern) for n in all_names):
                raise _no_match_error(pattern, "exclude", all_names)
        selected = [n for n in selected if not any(_matches(n, p) for p in exclude)]
        for pattern in ranges:
            if not any(_matches(n, pattern) for n in selected):
                raise _no_match_error(pattern, "ranges", selected or all_names)

        names: list[str] = []
        skipped: dict[str, str] = {}
        unused = {} if unused is None else dict(unused)
        for n in selected:
            if n in unused:
                skipped[n] = f"not used by the model: {unused[n]}"
                continue
            value = float(parameters[n])
            if not np.isfinite(value) or value < 0.0:
                raise ThermocalInputError(
                    f"parameter {n!r} has nominal value {value!r}; envelope parameters must be "
                    "finite and positive (fix the building file or exclude the parameter)"
                )
            if value == 0.0:
                skipped[n] = "nominal value is 0: a relative range is empty"
                continue
            names.append(n)
        if not names:
            why = "; ".join(f"{n}: {reason}" for n, reason in list(skipped.items())[:5])
            raise ThermocalInputError(
                "parameters: the include/exclude patterns select no parameter the model uses "
                f"with a non-zero nominal value (include={include}, exclude={exclude})"
                + (f"; left out: {why}" if why else "")
            )

        nominal = np.array([float(parameters[n]) for n in names])
        rel = _relative_ranges(names, ranges, default_range)
        extra = {} if limits is None else dict(limits)
        bounds = []
        for n, v in zip(names, nominal, strict=True):
            lo, hi = physical_limits(n, v, floor_fraction)
            if v <= hi / (1.0 - LIMIT_MARGIN) and v > hi:  # a nominal on the model's limit
                hi = float(v)
            model_lo, model_hi = extra.get(n, (lo, hi))
            bounds.append((max(lo, model_lo), min(hi, model_hi)))
        limit_lower = np.array([lo for lo, _ in bounds])
        limit_upper = np.array([hi for _, hi in bounds])
        for n, nom, hi in zip(names, nominal, limit_upper, strict=True):
            if nom > hi:
                raise ThermocalInputError(
                    f"parameter {n!r}: its nominal value {nom:g} exceeds the largest value the "
                    f"model accepts ({hi:g}); fix the building file"
                )
        return cls(
            names=tuple(names),
            nominal=nominal,
            relative_range=rel,
            range_lower=nominal * (1.0 - rel),
            range_upper=nominal * (1.0 + rel),
            limit_lower=limit_lower,
            limit_upper=limit_upper,
            floor_fraction=float(floor_fraction),
            skipped=skipped,
        )

    # ------------------------------------------------------------------------------------------
    def __len__(self) -> int:
        return len(self.names)

    @property
    def dimension(self) -> int:
        """Number of parameters [-]."""
        return len(self.names)

    @property
    def units(self) -> tuple[str, ...]:
        """Unit of each parameter, for tables."""
        return tuple(parameter_unit(n) for n in self.names)

    @property
    def lower(self) -> np.ndarray:
        """Lower bound of the values a sample can take (range clipped to the limits) [unit]."""
        return np.clip(self.range_lower, self.limit_lower, self.limit_upper)

    @property
    def upper(self) -> np.ndarray:
        """Upper bound of the values a sample can take (range clipped to the limits) [unit]."""
        return np.clip(self.range_upper, self.limit_lower, self.limit_upper)

    @property
    def clipped_lower(self) -> tuple[str, ...]:
        """Names whose sampling range extends below the physical lower limit."""
        return tuple(n for n, r, l in zip(self.names, self.range_lower, self.limit_lower,
                                          strict=True) if r < l)

    @property
    def clipped_upper(self) -> tuple[str, ...]:
        """Names whose sampling range extends above the physical upper limit."""
        return tuple(n for n, r, l in zip(self.names, self.range_upper, self.limit_upper,
                                          strict=True) if r > l)

    @property
    def clipped(self) -> tuple[str, ...]:
        """Names whose sampling range is clipped on either side."""
        both = set(self.clipped_lower) | set(self.clipped_upper)
        return tuple(n for n in self.names if n in both)

    def nominal_dict(self) -> dict[str, float]:
        """Nominal values by name [unit of each parameter]."""
        return {n: float(v) for n, v in zip(self.names, self.nominal, strict=True)}

    def index(self, name: str) -> int:
        """Position of a parameter; unknown names raise with a "did you mean"."""
        try:
            return self.names.index(name)
        except ValueError:
            close = difflib.get_close_matches(name, self.names, n=3, cutoff=0.5)
            hint = f"; did you mean {', '.join(repr(c) for c in close)}?" if close else ""
            raise ThermocalInputError(
                f"parameter {name!r} is not in the parameter space{hint}"
            ) from None

    def subset(self, names: Sequence[str]) -> ParameterSpace:
        """The same space restricted to ``names`` (in that order)."""
        idx = [self.index(n) for n in names]
        return ParameterSpace(
            names=tuple(self.names[i] for i in idx),
            nominal=self.nominal[idx],
            relative_range=self.relative_range[idx],
            range_lower=self.range_lower[idx],
            range_upper=self.range_upper[idx],
            limit_lower=self.limit_lower[idx],
            limit_upper=self.limit_upper[idx],
            floor_fraction=self.floor_fraction,
        )

    # ------------------------------------------------------------------------------------------
    def scale(self, unit_points: np.ndarray) -> np.ndarray:
        """Map points of the unit hypercube onto the unclipped sampling range.

        Parameters
        ----------
        unit_points : ndarray, shape (n, d)
            Points in [0, 1)^d [-].

        Returns
        -------
        ndarray, shape (n, d)
            ``range_lower + u * (range_upper - range_lower)`` [unit of each parameter]
            (not yet clipped).
        """
        u = np.asarray(unit_points, dtype=float)
        if u.ndim != 2 or u.shape[1] != self.dimension:
            raise ThermocalInputError(
                f"unit_points must have shape (n, {self.dimension}), got {u.shape}"
            )
        return self.range_lower + u * (self.range_upper - self.range_lower)

    def clip(self, values: np.ndarray) -> tuple[np.ndarray, pd.DataFrame]:
        """Clip values to the physical limits and count the clipped ones per parameter.

        Parameters
        ----------
        values : ndarray, shape (n, d)
            Parameter values [unit of each parameter].

        Returns
        -------
        clipped : ndarray, shape (n, d)
            Values inside ``[limit_lower, limit_upper]`` [unit of each parameter].
        counts : DataFrame
            Index: parameter names; columns ``lower``, ``upper``, ``total`` (number of values
            set to the lower/upper limit) and ``fraction`` (total / n) [-].
        """
        x = np.asarray(values, dtype=float)
        if x.ndim != 2 or x.shape[1] != self.dimension:
            raise ThermocalInputError(
                f"values must have shape (n, {self.dimension}), got {x.shape}"
            )
        below = x < self.limit_lower
        above = x > self.limit_upper
        out = np.clip(x, self.limit_lower, self.limit_upper)
        n = max(x.shape[0], 1)
        counts = pd.DataFrame(
            {
                "lower": below.sum(axis=0).astype(int),
                "upper": above.sum(axis=0).astype(int),
            },
            index=pd.Index(self.names, name="parameter"),
        )
        counts["total"] = counts["lower"] + counts["upper"]
        counts["fraction"] = counts["total"] / n
        return out, counts

    # ------------------------------------------------------------------------------------------
    def to_frame(self) -> pd.DataFrame:
        """Table of the space: unit, nominal, relative range, range, limits, effective bounds."""
        return pd.DataFrame(
            {
                "unit": self.units,
                "nominal": self.nominal,
                "relative_range": self.relative_range,
                "range_lower": self.range_lower,
                "range_upper": self.range_upper,
                "limit_lower": self.limit_lower,
                "limit_upper": self.limit_upper,
                "lower": self.lower,
                "upper": self.upper,
                "clipped": [n in set(self.clipped) for n in self.names],
            },
            index=pd.Index(self.names, name="parameter"),
        )

    def to_dict(self) -> dict:
        """JSON-ready definition (for fingerprints and reports); ``inf`` written as ``None``."""

        def fl(a: np.ndarray) -> list:
            return [None if not np.isfinite(v) else float(v) for v in a]

        return {
            "names": list(self.names),
            "nominal": fl(self.nominal),
            "relative_range": fl(self.relative_range),
            "limit_lower": fl(self.limit_lower),
            "limit_upper": fl(self.limit_upper),
            "floor_fraction": self.floor_fraction,
        }


def _relative_ranges(
    names: Sequence[str], ranges: Mapping[str, float], default_range: float
) -> np.ndarray:
    """Each parameter's relative half-width: that of the most specific ``ranges`` pattern
    matching it, else ``default_range``.

    A pattern is more specific than another when the parameters it matches are a strict subset
    of the other's (``{"material/*": 0.5, "material/insulation/*": 0.9}``: the insulation's
    +-90 %, whatever the order of the keys).

    Parameters
    ----------
    names : sequence of str
        The varied parameters [-].
    ranges : mapping of str to float
        ``fnmatch`` pattern -> relative half-width [-] (0.75 = +-75 %).
    default_range : float
        Relative half-width of the parameters no pattern matches [-].

    Returns
    -------
    ndarray
        Relative half-width of each of ``names`` [-].

    Raises
    ------
    ThermocalInputError
        Patterns giving one parameter different half-widths none of which is more specific
        than the others (naming the parameter and the patterns): which one counted depended on
        the order of the keys (``{"window/*": 0.9, "*/u_value": 0.1}`` crossing at a window's
        U-value when other U-values are varied too).
    """
    matched = {p: frozenset(n for n in names if _matches(n, p)) for p in ranges}
    relative = np.full(len(names), float(default_range))
    for i, name in enumerate(names):
        matching = [p for p in ranges if name in matched[p]]
        values = {float(ranges[p]) for p in matching}
        if len(values) > 1:
            narrowest = [
                p for p in matching if all(matched[p] < matched[q] for q in matching if q != p)
            ]
            if len(narrowest) != 1:
                listed = " and ".join(f"{p!r} (+-{100 * float(ranges[p]):g} %)" for p in matching)
                raise ThermocalInputError(
                    f"parameters.ranges: parameter {name!r} matches {listed}, which give it "
                    "different ranges and none of which matches only a part of what the others "
                    "match (the most specific pattern counts); narrow a pattern (e.g. "
                    "'window/*/shgc' instead of 'window/*'), or give them the same range"
                )
            values = {float(ranges[narrowest[0]])}
        if values:
            relative[i] = values.pop()
    return relative


def _check_range(what: str, value: object) -> None:
    try:
        v = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ThermocalInputError(
            f"{what} must be a number (relative half-width, 0.75 = +-75 %), got {value!r}"
        ) from None
    if not np.isfinite(v) or v < 0.0:
        raise ThermocalInputError(
            f"{what} must be a non-negative relative half-width (0.75 = +-75 %), got {value!r}"
        )
