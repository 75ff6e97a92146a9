"""Inputs a campaign does not vary but does not know either, marginalised in the posterior.

A campaign varies some parameters and holds every other one at its nominal value. When one of
those others is wrong (the infiltration without a pressurisation test is the common case), the
calibrated parameters absorb its error and their intervals, computed as if it were exact, miss
their truth: on the EnergyPlus twin of the DOE outpatient prototype (infiltration x1.4 hidden,
not varied) the roof's resistance came out determined with its 90 % interval wholly below the
truth. The Bayesian answer is to treat such an input as a nuisance parameter with a prior and
integrate it out (Kennedy and O'Hagan 2001, their "calibration inputs" against the known
"variable inputs"; Gelman et al. 2013, chapter 3).

The posterior's model is affine in the parameters' coordinates (their logarithms in the published
form; :mod:`thermocal.calibration.coordinates`) and the input enters through its own logarithm, so
one more model run per uncertain input gives the exact marginal: the input scaled by ``exp(s)``
(``s`` its prior standard deviation in the log, from a relative standard uncertainty ``r`` as ``s^2
= ln(1 + r^2)``) changes the unoccupied-heat series by ``s`` times its signature; with the input's
log ``u ~ N(0, s^2)`` the series' covariance gains ``s^2 b b^T`` (``b`` the signature per unit
log), added to the likelihood beside the model discrepancy
(:func:`thermocal.calibration.posterior.calibration_posterior`, ``uncertain``). The runs are kept
in the campaign's store like the analysis' other runs: a re-analysis reads them.

The campaign file names the inputs in ``posterior.uncertain``: a parameter name or pattern
(``fnmatch``) -> its relative standard uncertainty; all parameters a pattern matches are scaled
together (one input: a building-wide error, e.g. ``infiltration/building/factor``). The value
``auto`` marks the building's infiltration uncertain by :data:`INFILTRATION_REL_STD` when the
campaign varies no infiltration parameter and the building has any; the default is none.

A calibrated parameter that compensates an input (posterior correlation beyond 0.7 in magnitude
in their joint Gaussian) is then not called determined: the input's prior, an assumption, sets
it rather than the data. The marginal is exact for the posterior's log-affine model given its
noise level, with two approximations: the signature is a one-sided difference at one standard
deviation (for a heat that is linear in the input, e.g. an air change, it over-states the
input's variance by about 19 % at 40 %), and it is taken at the nominal point of the campaign's
parameters (also in the zoom stage, whose box is elsewhere). Measured on the EnergyPlus twins
(2026-11-29, docs/calibration.md, "Inputs the campaign holds nominal but does not know").

References
----------
.. [1] Kennedy M.C., O'Hagan A. (2001), Bayesian calibration of computer models, Journal of
   the Royal Statistical Society B 63, 425-464.
.. [2] Gelman A., Carlin J.B., Stern H.S., Dunson D.B., Vehtari A., Rubin D.B. (2013),
   Bayesian Data Analysis, 3rd edition, CRC Press (chapter 3: nuisance parameters).
"""

from __future__ import annotations

import fnmatch
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from thermocal.errors import ThermocalInputError

__all__ = [
    "INFILTRATION_REL_STD",
    "UncertainInput",
    "model_refusal",
    "nominal_values",
    "uncertain_inputs",
    "uncertain_signatures",
]

#: Relative standard uncertainty of a building's infiltration that no test measured [-]: the
#: ``auto`` default, thermocal's assumption for an air-change rate taken from a building's
#: description rather than a pressurisation test (ISO 9972): log-normal with a factor of about
#: 1.47 at one standard deviation, so that a rate off by a factor 1.5 either way is plausible.
INFILTRATION_REL_STD = 0.4


@dataclass(frozen=True)
class UncertainInput:
    """One uncertain input: the parameters it scales together and its prior.

    Attributes
    ----------
    label : str
        The name or pattern it was given by.
    rel_std : float
        Relative standard uncertainty [-].
    nominal : dict of str to float
        The parameters it scales and their nominal values [unit of each].
    direction : {1, -1}
        The side of the signature's run: up by one standard deviation, or down where up leaves
        a parameter's valid range (a window's SHGC near 1) [-].
    """

    label: str
    rel_std: float
    nominal: dict
    direction: int = 1

    @property
    def log_sd(self) -> float:
        """Prior standard deviation of the input's log, ``sqrt(ln(1 + r^2))`` [-]."""
        return float(np.sqrt(np.log1p(self.rel_std**2)))

    @property
    def step(self) -> float:
        """The signature run's change of the input's log, ``direction * log_sd`` [-]."""
        return self.direction * self.log_sd

    def perturbed(self) -> dict[str, float]:
        """The parameters scaled by ``exp(step)``: the run that gives the signature
        [unit of each]."""
        factor = float(np.exp(self.step))
        return {name: value * factor for name, value in self.nominal.items()}

    def description(self) -> dict:
        """``label``, ``rel_std`` and ``parameters`` (sorted names), JSON-ready."""
        return {
            "label": self.label,
            "rel_std": float(self.rel_std),
            "parameters": sorted(self.nominal),
        }


def nominal_values(building) -> dict[str, float]:
    """Every parameter a campaign's problem accepts, with its nominal value.

    The material fields and zone rates of :meth:`Building.parameters` and the names of
    :func:`thermocal.identification.problem.element_nominal_values`, as
    :class:`thermocal.identification.problem.IdentificationProblem` accepts them.

    Parameters
    ----------
    building : thermocal.multizone.Building

    Returns
    -------
    dict of str to float
        [unit of each parameter]
    """
    from thermocal.identification.problem import element_nominal_values

    return {**building.parameters(), **element_nominal_values(building)}


def model_refusal(building):
    """``invalid`` for :func:`uncertain_inputs`: why ``building`` refuses parameter values.

    Parameters
    ----------
    building : thermocal.multizone.Building

    Returns
    -------
    callable
        ``parameters`` -> the model's message (text) or None when it accepts them.
    """

    def refusal(parameters: Mapping[str, float]) -> str | None:
        try:
            building.with_parameters(dict(parameters))
        except ThermocalInputError as exc:
            return str(exc)
        return None

    return refusal


def _is_infiltration(name: str) -> bool:
    return name.endswith("/infiltration_ach") or name.startswith("infiltration/")


def _is_zone_rate(name: str) -> bool:
    """A zone's or a zone group's own air change rate (not the building-wide factor)."""
    from thermocal.multizone.parameters import INFILTRATION_FACTOR

    return _is_infiltration(name) and name != INFILTRATION_FACTOR


def uncertain_inputs(
    spec,
    nominal: Mapping[str, float],
    varied: Sequence[str],
    *,
    where: str = "posterior",
    invalid=None,
) -> list[UncertainInput]:
    """The uncertain inputs of a campaign from its ``posterior.uncertain`` setting.

    Parameters
    ----------
    spec : dict of str to float, or "auto"
        Parameter name or ``fnmatch`` pattern -> relative standard uncertainty [-]; ``"auto"``:
        the building-wide infiltration factor by :data:`INFILTRATION_REL_STD` when no
        infiltration parameter is varied and some zone has infiltration; ``{}``: none.
    nominal : mapping
        Every parameter the problem accepts and its nominal value (:func:`nominal_values`)
        [unit of each].
    varied : sequence of str
        The campaign's parameters.
    where : str
        The setting's place, for messages.
    invalid : callable, optional
        ``invalid(parameters)`` -> why the model refuses these parameter values (a text) or
        None; the signature's run then goes down by one standard deviation instead of up, and
        an input refused both ways is an error. Default: every value accepted.

    Returns
    -------
    list of UncertainInput

    Raises
    ------
    ThermocalInputError
        A pattern that matches no parameter, matches one the campaign varies (it is calibrated,
        not uncertain) or scales what a varied parameter scales (the building's infiltration
        factor and the zones' own rates), matches only parameters whose nominal value is zero
        (scaling changes nothing), an uncertainty that is not in (0, 2], or an input whose
        values one standard deviation either way the model refuses.
    """
    from thermocal.multizone.parameters import INFILTRATION_FACTOR

    varied = set(varied)
    if spec == "auto":
        has_infiltration = any(value > 0 for name, value in nominal.items() if _is_zone_rate(name))
        if not has_infiltration or any(_is_infiltration(n) for n in varied):
            return []
        spec = {INFILTRATION_FACTOR: INFILTRATION_REL_STD}
    out = []
    for pattern, rel_std in dict(spec).items():
        key = f"{where}.uncertain[{pattern!r}]"
        if not (isinstance(rel_std, int | float) and 0 < rel_std <= 2):
            raise ThermocalInputError(
                f"{key}: the relative standard uncertainty must be a number in (0, 2] (0.3 for "
                f"+-30 %), got {rel_std!r}"
            )
        matched = sorted(n for n in nominal if fnmatch.fnmatchcase(n, pattern))
        if not matched:
            import difflib

            close = sorted(n for n in nominal if fnmatch.fnmatchcase(n.lower(), pattern.lower()))
            close = close or difflib.get_close_matches(pattern, list(nominal), n=3)
            hint = f" (did you mean {', '.join(close[:3])}?)" if close else ""
            raise ThermocalInputError(
                f"{key}: matches no parameter of the building{hint}; parameters are named "
                "material/<material>/<field>, construction/<construction>/resistance, "
                "window/<type>/u_value, zone/<zone>/infiltration_ach or "
                f"'{INFILTRATION_FACTOR}' (patterns with * allowed)"
            )
        calibrated = [n for n in matched if n in varied]
        if calibrated:
            raise ThermocalInputError(
                f"{key}: {calibrated[0]!r} is varied by the campaign (it is calibrated, not an "
                "uncertain input); name only parameters the campaign holds at their nominal "
                "values"
            )
        if INFILTRATION_FACTOR in matched and len(matched) > 1:
            raise ThermocalInputError(
                f"{key}: matches {INFILTRATION_FACTOR!r} and the zones' own rates, which it "
                "scales; give one of the two"
            )
        scales_varied = (INFILTRATION_FACTOR in matched and any(map(_is_zone_rate, varied))) or (
            INFILTRATION_FACTOR in varied and any(map(_is_zone_rate, matched))
        )
        if scales_varied:
            raise ThermocalInputError(
                f"{key}: scales the air change rates the campaign varies (the building's "
                "infiltration factor multiplies every zone's rate); the data cannot tell the "
                "two apart: leave it out, or vary the infiltration one way only"
            )
        scaled = {n: float(nominal[n]) for n in matched if float(nominal[n]) != 0.0}
        if not scaled:
            raise ThermocalInputError(
                f"{key}: every parameter it matches is zero ({', '.join(matched[:3])}); "
                "scaling it changes nothing"
            )
        item = UncertainInput(str(pattern), float(rel_std), scaled)
        if invalid is not None:
            item = _valid_side(item, invalid, key)
        out.append(item)
    return out


def _valid_side(item: UncertainInput, invalid, key: str) -> UncertainInput:
    """``item`` with the side of its signature run the model accepts (up, else down)."""
    from dataclasses import replace

    why = invalid(item.perturbed())
    if why is None:
        return item
    down = replace(item, direction=-1)
    why_down = invalid(down.perturbed())
    if why_down is None:
        return down
    raise ThermocalInputError(
        f"{key}: the model refuses the input one standard deviation either way ({why}; "
        f"{why_down}); give a smaller relative uncertainty"
    )


def uncertain_signatures(inputs: Sequence[UncertainInput], run, nominal_outputs, metric: str):
    """Each input's signature on the posterior's series, from one model run per input.

    Parameters
    ----------
    inputs : sequence of UncertainInput
    run : callable
        ``run(item)`` -> the outputs (as a sample's) of the run with ``item.perturbed()``,
        or None when it is neither stored nor may be simulated (a re-analysis) or failed
        [unit of each].
    nominal_outputs : mapping
        The nominal model's outputs [unit of each].
    metric : {"building", "groups"}
        The campaign's metric (which series the posterior uses).

    Returns
    -------
    signatures : list of (dict, ndarray, float)
        Per available input its description, signature per unit log [W] and prior variance of
        the log [-] (the ``uncertain`` argument of
        :func:`thermocal.calibration.posterior.calibration_posterior`).
    missing : list of str
        The labels of inputs whose run is not available.

    Raises
    ------
    ThermocalInputError
        The stored outputs hold no heat series (a store written before they were stored).
    """
    import pandas as pd

    from thermocal.calibration.metric import metric_data

    signatures, missing = [], []
    for item in inputs:
        outputs = run(item)
        if outputs is None:
            missing.append(item.label)
            continue
        frame = pd.DataFrame([dict(nominal_outputs), dict(outputs)])
        _, series, _ = metric_data(frame, metric)
        if series is None:
            raise ThermocalInputError(
                "posterior.uncertain needs the unoccupied heat series of the nominal run, "
                "which this campaign's store does not hold; run the campaign again into a new "
                "store"
            )
        signature = (series[1] - series[0]) / item.step
        signatures.append((item.description(), signature, item.log_sd**2))
    return signatures, missing
