"""The spatial metric: the unoccupied identified heat per zone group, not only its building sum.

The published metric sums the identified heat ``Q_ID`` of all zones before taking its variance
over the unoccupied hours. An error of the roof shows in the zones under the roof, an error of
the walls in the perimeter zones of each facade; in the building sum they add up and partly
cancel (``var(a + b) = var(a) + var(b) + 2 cov(a, b)``), so the sum cannot tell them apart as
well as the parts can. Here the tracked zones are grouped by what their envelope is made of
(:func:`zone_groups`: floor position from the roof and ground surfaces, orientation of the
largest exterior wall or "core"), every sample stores the hourly means of each group's
identified heat over the unoccupied steps, and the *groups* metric is the joint least-squares
criterion on these series, ``sum_g var_h(q_g(h))`` [W^2]: each group's heat should be constant
when the envelope is right (beyond the paper).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError

__all__ = [
    "CampaignEvaluator",
    "group_metric",
    "group_outputs",
    "group_segments",
    "zone_groups",
]

#: metric names of the campaign file's ``metric`` key
METRICS = ("building", "groups")


def zone_groups(building, zones: Sequence[str]) -> dict[str, str]:
    """The envelope group of each zone: floor position and orientation.

    Parameters
    ----------
    building : thermocal.multizone.Building
    zones : sequence of str
        The tracked zones (the others carry no identified heat).

    Returns
    -------
    dict of str to str
        Zone -> group label, e.g. ``"top floor, 180 deg"``, ``"ground floor, core"``; the
        floor position is "roof and ground" for a single-storey zone (both a roof and a
        ground floor), "top floor" (roof only), "ground floor" (ground only) or "middle
        floor"; the orientation is the azimuth of the zone's largest exterior wall rounded to
        45 degrees, or "core" without an exterior wall.
    """
    from thermocal.identification.sensors import main_orientation
    from thermocal.multizone.elements import surface_role

    roles: dict[str, set[str]] = {zone: set() for zone in zones}
    for surface in building.surfaces.values():
        if surface.zone in roles:
            roles[surface.zone].add(surface_role(surface))
    out = {}
    for zone in zones:
        if zone not in building.zones:
            raise ThermocalInputError(f"zone groups: {zone!r} is not a zone of the building")
        roof = "roof" in roles[zone]
        ground = bool({"ground_floor", "ground_wall"} & roles[zone])
        floor = {
            (True, True): "roof and ground",
            (True, False): "top floor",
            (False, True): "ground floor",
            (False, False): "middle floor",
        }[(roof, ground)]
        orientation = main_orientation(building, zone)
        out[zone] = f"{floor}, {'core' if orientation == 'interior' else orientation}"
    return out


def group_outputs(
    heat: pd.DataFrame, mask: np.ndarray, groups: Mapping[str, str], labels: Sequence[str]
) -> dict[str, float]:
    """Hourly means of each group's identified heat over the unoccupied steps.

    Parameters
    ----------
    heat : DataFrame (steps x zones)
        Identified heat per zone [W].
    mask : ndarray of bool (steps,)
        The unoccupied steps of the metric.
    groups : mapping of zone -> group label
    labels : sequence of str
        The groups in their stored order.

    Returns
    -------
    dict
        ``group/<g>/<hour>`` [W], ``g`` the group's position in ``labels`` (two digits) and
        the hours numbered in time order (five digits), as the building series ``series/``.
    """
    index = heat.index[mask]
    hour = index.floor("1h")
    out = {}
    for g, label in enumerate(labels):
        columns = [z for z, lab in groups.items() if lab == label and z in heat.columns]
        total = heat[columns].to_numpy()[mask].sum(axis=1)
        means = pd.Series(total, index=index).groupby(hour).mean().to_numpy()
        out.update({f"group/{g:02d}/{i:05d}": float(v) for i, v in enumerate(means)})
    return out


def group_segments(columns: Sequence[str]) -> tuple[list[str], list[tuple[int, int]]]:
    """The stored group-series columns in order and each group's column range.

    Parameters
    ----------
    columns : sequence of str
        Output names of a campaign (``group/<g>/<hour>`` among them).

    Returns
    -------
    (list of str, list of (start, stop))
        Sorted group columns; the half-open column range of each group in that list.
    """
    ordered = sorted(c for c in columns if c.startswith("group/"))
    segments: list[tuple[int, int]] = []
    previous = None
    for i, name in enumerate(ordered):
        g = name.split("/")[1]
        if g != previous:
            segments.append((i, i + 1))
            previous = g
        else:
            segments[-1] = (segments[-1][0], i + 1)
    return ordered, segments


def group_metric(series: np.ndarray, segments: Sequence[tuple[int, int]]) -> np.ndarray:
    """The groups metric: the sum over the groups of the variance of their hourly series.

    Parameters
    ----------
    series : ndarray (n_samples, n_columns) or (n_columns,)
        Concatenated hourly group series [W].
    segments : sequence of (start, stop)
        Column range of each group.

    Returns
    -------
    ndarray (n_samples,) or float
        ``sum_g var_h(q_g(h))`` [W^2].
    """
    s = np.atleast_2d(np.asarray(series, dtype=float))
    total = np.zeros(s.shape[0])
    for start, stop in segments:
        total += s[:, start:stop].var(axis=1)
    return total if np.ndim(series) == 2 else float(total[0])


@dataclass
class CampaignEvaluator:
    """The campaign's evaluator: the identification problem's outputs plus the group series.

    Picklable (the problem builds its simulation once per worker); ``evaluate(parameters)``
    returns :meth:`IdentificationProblem.metrics` and :func:`group_outputs`.

    Attributes
    ----------
    problem : IdentificationProblem
    groups : dict of zone -> group label
    labels : list of str
        The groups in their stored order.
    """

    problem: object
    groups: dict
    labels: list

    def outputs(self, heat: pd.DataFrame) -> dict[str, float]:
        """All stored outputs of one run from its identified heat per zone [W]."""
        from thermocal.identification.metrics import unoccupied_steps

        problem = self.problem
        out = problem.metrics(heat)
        mask = unoccupied_steps(heat.index, problem.schedule, settle=problem.settle)
        out.update(group_outputs(heat, mask, self.groups, self.labels))
        return out

    def evaluate(self, parameters: Mapping[str, float]) -> dict[str, float]:
        """The outputs for one parameter set (others nominal), from the identified heat alone
        (:meth:`IdentificationProblem.identified_heat`: the tracking result's temperature
        frames are not built)."""
        return self.outputs(self.problem.identified_heat_frame(parameters))


def campaign_evaluator(problem, building) -> CampaignEvaluator:
    """The evaluator of ``problem`` with the envelope groups of its tracked zones."""
    zones = [z for z in building.zones if z in problem.reference.columns]
    groups = zone_groups(building, zones)
    labels = sorted(set(groups.values()))
    return CampaignEvaluator(problem, groups, labels)
