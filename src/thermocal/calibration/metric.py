"""The metric of a campaign (the building-wide or zone-group unoccupied variance of the
identified heat), read from stored samples or from one run.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from thermocal.errors import ThermocalInputError
from thermocal.identification.problem import METRIC

#: what each metric of the campaign file's ``metric`` key is, for calibration.json and the report
METRIC_NAMES = {
    "building": "unoccupied variance of the building-wide identified heat",
    "groups": "sum over the zone groups of the unoccupied variance of their hourly identified heat",
}


def metric_data(outputs: pd.DataFrame, metric: str):
    """The chosen metric of every sample, and the series of its series meta-model.

    Parameters
    ----------
    outputs : DataFrame
        The samples' stored outputs (:meth:`CampaignStore.outputs`).
    metric : {"building", "groups"}

    Returns
    -------
    y : ndarray [W^2]
    series : ndarray (samples, columns) [W] or None
    segments : list of (start, stop) or None
        Column range of each series (one per zone group; None: one series).
    """
    from thermocal.calibration.spatial import group_metric, group_segments

    if metric == "building":
        columns = sorted(c for c in outputs.columns if c.startswith("series/"))
        series = outputs[columns].to_numpy(dtype=float) if columns else None
        return outputs[METRIC].to_numpy(dtype=float), series, None
    columns, segments = group_segments(list(outputs.columns))
    if not columns:
        raise ThermocalInputError(
            "metric: groups needs the zone-group heat series of every sample, which this "
            "campaign's store does not hold (written before they were stored); use metric: "
            "building, or run the campaign again into a new store"
        )
    series = outputs[columns].to_numpy(dtype=float)
    return group_metric(series, segments), series, segments


def metric_value(outputs: dict, metric: str) -> float:
    """The chosen metric of one run's outputs [W^2]."""
    from thermocal.calibration.spatial import group_metric, group_segments

    if metric == "building":
        return float(outputs[METRIC])
    columns, segments = group_segments(list(outputs))
    return group_metric(np.array([outputs[c] for c in columns], dtype=float), segments)
