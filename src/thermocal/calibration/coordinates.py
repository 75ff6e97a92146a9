"""Coordinates in which the series meta-model is affine: how the heat depends on each parameter.

The series meta-model (:class:`~thermocal.calibration.surrogate.SeriesSurrogate`) regresses the
hourly identified heat on a coordinate ``z`` of each parameter, zero at the nominal value. The
published form uses ``z = log(p / p_nominal)`` for every parameter. The heat through an element
does not go as the logarithm of its resistance but as its conductance ``1 / (R + R_films)``,
and the heat of an air change or a window goes as the rate, the U-value or the SHGC
themselves; over a +-75 % prior a straight line in ``log p`` then puts the zero of a
resistance's signature several per cent off (an EnergyPlus twin's roof +21 %; docs/calibration.md,
"Curvature of the series meta-model"). In *physical* coordinates the regression is affine in
what the heat is affine in, with no more coefficients than the published form:

* ``construction/<name>/resistance`` (the layers' resistance ``R``): minus the relative change
  of its conductance ``U = 1 / (R + R_f)``, ``z = 1 - U / U_0 = 1 - (R_0 + R_f) / (R + R_f)``
  (increasing in ``R``), with the surface films of ISO 6946
  (:data:`FILM_RESISTANCE`, ``R_si + R_se`` for horizontal heat flow);
* window ``u_value`` and ``shgc``, air change rates (``infiltration_ach``, ``ach``) and the
  building's infiltration ``factor``: the relative change itself, ``z = p / p_0 - 1``;
* every other parameter (layer conductivity, density, specific heat, thickness, a single
  layer's resistance, heat capacity): ``z = log(p / p_0)`` as published, since its heat has no
  such closed form (a layer's conductivity acts through the rest of its construction).

Every coordinate is increasing in ``p``, so a box of parameters is a box of coordinates and the
bounded least squares, vertex searches and truncated-Gaussian sampling in ``z`` keep their form.
The posterior's prior stays uniform in each parameter: its density in ``z`` is ``exp(z)`` for a
logarithm (a linear tilt, exact in the Gibbs sweeps), constant for a linear coordinate and
``(1 - z)^-2`` for a conductance (in that coordinate's Gibbs conditional, its logarithm
interpolated on 32 pieces; exact in the ensemble sampler).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from thermocal.errors import ThermocalInputError
from thermocal.multizone.parameters import parameter_kind

__all__ = [
    "COORDINATE_SYSTEMS",
    "FILM_RESISTANCE",
    "coordinate_kinds",
    "coordinate_slope",
    "from_coordinates",
    "to_coordinates",
]

#: The coordinate systems a series meta-model can use: ``physical`` (see the module) or ``log``
#: (the published form: the logarithm of every parameter).
COORDINATE_SYSTEMS = ("physical", "log")

#: Surface resistances added to a construction's layers in its conductance coordinate: ISO 6946
#: ``R_si + R_se`` = 0.13 + 0.04 m2 K/W (horizontal heat flow; 0.14 upwards, 0.21 downwards:
#: the coordinate's curvature, not its zero, depends on them) [m2 K/W].
FILM_RESISTANCE = 0.17

#: Kinds whose heat is proportional to the parameter itself.
LINEAR_KINDS = frozenset({"u_value", "shgc", "infiltration_ach", "ach", "factor"})


def coordinate_kinds(names: Sequence[str], system: str = "physical") -> tuple[str, ...]:
    """The coordinate of each parameter: ``"conductance"``, ``"linear"`` or ``"log"``.

    Parameters
    ----------
    names : sequence of str
        Parameter names (:meth:`thermocal.multizone.Building.parameters`).
    system : {"physical", "log"}
        ``log`` gives ``"log"`` for every parameter (the published form).

    Returns
    -------
    tuple of str
    """
    if system not in COORDINATE_SYSTEMS:
        raise ThermocalInputError(
            f"series meta-model: coordinates {system!r} unknown; use one of "
            f"{', '.join(COORDINATE_SYSTEMS)}"
        )
    if system == "log":
        return tuple("log" for _ in names)
    out = []
    for name in names:
        kind = parameter_kind(name)
        if kind == "resistance" and str(name).startswith("construction/"):
            out.append("conductance")
        elif kind in LINEAR_KINDS:
            out.append("linear")
        else:
            out.append("log")
    return tuple(out)


def _check_positive(values: np.ndarray, nominal: np.ndarray) -> None:
    if np.any(values <= 0) or np.any(nominal <= 0):
        raise ThermocalInputError(
            "series meta-model: parameters must be positive (their coordinates are relative "
            "to the nominal values)"
        )


def to_coordinates(values, nominal, kinds: Sequence[str]) -> np.ndarray:
    """Coordinates ``z`` of parameter values (rows) [-].

    Parameters
    ----------
    values : array-like (..., d)
        Parameter values [unit of each parameter].
    nominal : array-like (d,)
        Nominal values, where ``z = 0`` [unit of each parameter].
    kinds : sequence of str (d)
        From :func:`coordinate_kinds`.

    Returns
    -------
    ndarray (..., d) [-]
    """
    values = np.asarray(values, dtype=float)
    nominal = np.asarray(nominal, dtype=float)
    _check_positive(values, nominal)
    kinds = np.asarray(kinds)
    ratio = values / nominal
    z = np.log(ratio)
    linear = kinds == "linear"
    z = np.where(linear, ratio - 1.0, z)
    conductance = kinds == "conductance"
    if conductance.any():
        with np.errstate(divide="ignore", invalid="ignore"):
            g = 1.0 - (nominal + FILM_RESISTANCE) / (values + FILM_RESISTANCE)
        z = np.where(conductance, g, z)
    return z


def from_coordinates(z, nominal, kinds: Sequence[str]) -> np.ndarray:
    """Parameter values of coordinates ``z`` (the inverse of :func:`to_coordinates`).

    Parameters
    ----------
    z : array-like (..., d) [-]
    nominal : array-like (d,) [unit of each parameter]
    kinds : sequence of str (d)

    Returns
    -------
    ndarray (..., d) [unit of each parameter]
    """
    z = np.asarray(z, dtype=float)
    nominal = np.asarray(nominal, dtype=float)
    kinds = np.asarray(kinds)
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        out = nominal * np.exp(z)
        out = np.where(kinds == "linear", nominal * (1.0 + z), out)
        conductance = (nominal + FILM_RESISTANCE) / (1.0 - z) - FILM_RESISTANCE
        out = np.where(kinds == "conductance", conductance, out)
    return out


def coordinate_slope(values, nominal, kinds: Sequence[str]) -> np.ndarray:
    """``dz / d log p`` at parameter values [-] (the delta method's factor from a relative
    uncertainty to one in ``z``).

    Parameters
    ----------
    values : array-like (..., d) [unit of each parameter]
    nominal : array-like (d,) [unit of each parameter]
    kinds : sequence of str (d)

    Returns
    -------
    ndarray (..., d) [-]
    """
    values = np.asarray(values, dtype=float)
    nominal = np.asarray(nominal, dtype=float)
    kinds = np.asarray(kinds)
    slope = np.ones(np.broadcast(values, nominal).shape)
    slope = np.where(kinds == "linear", values / nominal, slope)
    conductance = (nominal + FILM_RESISTANCE) * values / (values + FILM_RESISTANCE) ** 2
    return np.where(kinds == "conductance", conductance, slope)
