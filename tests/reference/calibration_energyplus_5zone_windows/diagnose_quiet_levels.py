"""Why the SHGC is pulled upward with the window's temperature table right: the quiet hours hold
two levels of gains.

Run from the repository root after ``make_reference.py`` (about 5 s)::

    PYTHONPATH=src python \
        tests/reference/calibration_energyplus_5zone_windows/diagnose_quiet_levels.py

The campaign's metric assumes the internal heat constant over its quiet hours. The file's
equipment schedule ``EQUIP-1`` idles at 0.02 on weekday nights and at 0.2 all weekend, and the
quiet hours found in the data hold both. Two measurements at the truth (every varied parameter
at ``truth.json``'s value), written to ``quiet_levels.json``:

- ``classes``: per zone group, the quiet hours' identified heat about its mean [W] on weekdays,
  weekend days (08-18 h) and weekend nights, at the truth's SHGC, and how much an SHGC of 0.85
  lowers it in each class;
- ``slices``: the zone-group metric [W^2] along each parameter (the others at the truth), as the
  campaign computes it (``one level``: each group's variance over its quiet hours) and with one
  level per day type (``two levels``: the sum over the groups of the weekday and the weekend
  hours' variances, each about its own mean).
"""

from __future__ import annotations

import json
import tempfile
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
from calibrate_twin import (  # this folder's script (run as a script: its folder is on the path)
    FLOOR,
    HERE,
    INCLUDE,
    ROOF,
    WALL,
    WINDOW_SHGC,
    WINDOW_U,
    prepare,
    truth_file,
)

#: parameter -> values of its slice
SLICES = {
    WINDOW_SHGC: (0.70, 0.744, 0.80, 0.85),
    ROOF: (2.3, 2.553, 2.8, 3.04),
    WALL: (2.04, 2.2, 2.451, 2.7),
    WINDOW_U: (1.5, 1.794, 2.1),
    FLOOR: (0.12, 0.136, 0.155, 0.18),
}


def quiet_group_series(problem, evaluator, point: dict) -> dict:
    """Each group's hourly identified heat over the metric's quiet hours [W] at ``point``."""
    from thermocal.identification.metrics import unoccupied_steps

    heat = problem.run(point).heat
    mask = unoccupied_steps(heat.index, problem.schedule, settle=problem.settle)
    index = heat.index[mask]
    out = {}
    for label in sorted(set(evaluator.groups.values())):
        columns = [z for z, g in evaluator.groups.items() if g == label]
        total = heat[columns].to_numpy()[mask].sum(axis=1)
        out[label] = pd.Series(total, index=index).groupby(index.floor("1h")).mean()
    return out


def weekend(index: pd.DatetimeIndex) -> np.ndarray:
    """True on Saturdays and Sundays."""
    return np.asarray(index.dayofweek >= 5)


def one_and_two_levels(series: dict) -> tuple[float, float]:
    """The metric with one level and with one level per day type [W^2]."""
    one = sum(float(s.var(ddof=0)) for s in series.values())
    two = 0.0
    for s in series.values():
        rest = weekend(s.index)
        two += float(s[rest].var(ddof=0)) + float(s[~rest].var(ddof=0))
    return one, two


def classes(base: dict, more_sun: dict) -> dict:
    """Per group: mean heat about the group's mean by day class, and the change with more sun."""
    out = {}
    for label, s in base.items():
        rest, hour = weekend(s.index), s.index.hour
        day = (hour >= 8) & (hour < 18)
        parts = {"weekday": ~rest, "weekend day": rest & day, "weekend night": rest & ~day}
        change = more_sun[label] - s
        out[label] = {
            name: {
                "hours": int(m.sum()),
                "heat_about_mean_W": float((s - s.mean())[m].mean()),
                "change_with_shgc_0.85_W": float(change[m].mean()),
            }
            for name, m in parts.items()
        }
    return out


def run() -> dict:
    """Both measurements; writes ``quiet_levels.json``."""
    from thermocal.calibration.config import load_campaign
    from thermocal.calibration.spatial import campaign_evaluator
    from thermocal.calibration.workflow import build_problem, choose_quiet_hours, load_inputs

    with tempfile.TemporaryDirectory() as tmp, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        campaign = load_campaign(prepare(Path(tmp), 48))
        truth = {n: truth_file()["truth"][n] for n in INCLUDE}
        inputs = load_inputs(campaign)
        problem, _ = build_problem(campaign, inputs)
        evaluator = campaign_evaluator(problem, inputs.building)
        nominal = problem.run({})
        problem.schedule, _ = choose_quiet_hours(
            campaign, nominal.heat.sum(axis=1), log=lambda s: None
        )
        at_truth = quiet_group_series(problem, evaluator, truth)
        sunnier = quiet_group_series(problem, evaluator, {**truth, WINDOW_SHGC: 0.85})
        out = {"classes": classes(at_truth, sunnier), "slices": {}}
        for name, values in SLICES.items():
            rows = {}
            for value in values:
                one, two = one_and_two_levels(
                    quiet_group_series(problem, evaluator, {**truth, name: value})
                )
                rows[f"{value:.4g}"] = {"one level": round(one), "two levels": round(two)}
            out["slices"][name] = rows
    (HERE / "quiet_levels.json").write_text(json.dumps(out, indent=1) + "\n")
    return out


if __name__ == "__main__":
    print(json.dumps(run(), indent=1))
