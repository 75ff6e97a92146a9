"""Why the roof's 90 % interval misses the truth on the clinic twin: the meta-model's error at
the truth against its typical error.

The clinic twin's truth is in thermocal's own model class and its sensors are perfect, so the
only error the posterior meets is the series meta-model's (affine in the log-parameters). This
script runs the campaign of ``compare_metrics.py`` (element level, 48 samples, building-total
metric), fits the series meta-model on it as the posterior does, simulates the true envelope
and compares, hour by hour (centred over the hours):

- the meta-model's error at the truth (predicted minus simulated series) with the root mean
  square of its out-of-fold errors over the campaign's samples;
- the shift of the best fit that this error alone causes (least squares of the hour-centred
  Jacobian on it, in log-parameters and as a factor on each parameter), with the posterior's
  90 % interval widths.

Run: PYTHONPATH=src python tests/reference/calibration_spatial/diagnose_roof.py
"""

from __future__ import annotations

import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np
import pandas as pd

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE.parents[1] / "calibration"))


def main() -> int:
    warnings.simplefilter("ignore")
    from test_calibration_workflow import _campaign, _clinic

    from thermocal.calibration.config import load_campaign
    from thermocal.calibration.posterior import emulator_variance, linear_heat_model
    from thermocal.calibration.spatial import campaign_evaluator
    from thermocal.calibration.store import CampaignStore
    from thermocal.calibration.workflow import (
        build_problem,
        calibrate,
        choose_quiet_hours,
        load_inputs,
        metric_data,
        surrogate_for,
    )
    from thermocal.multizone.elements import element_parameters

    nominal = _clinic()
    start = element_parameters(nominal)
    wall, roof = "construction/Exterior wall/resistance", "construction/Roof/resistance"
    truth = {wall: 0.6 * start[wall], roof: 1.5 * start[roof]}
    parameters = """parameters:
  level: element
  include: ["construction/Exterior wall/*", "construction/Roof/resistance",
            "window/Exterior window/u_value", "infiltration/corridor 1/ach"]
  default_range: 0.6"""
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        path = _campaign(folder, samples=48, truth=truth, parameters=parameters)
        campaign = load_campaign(path)
        result = calibrate(
            campaign, workers=1, store_path=folder / "s.sqlite", progress=False, log=print
        )
        space = result.space
        with CampaignStore.existing(folder / "s.sqlite") as store:
            X = store.parameters()[list(space.names)]
            outputs = store.outputs()
        y, series, segments = metric_data(outputs, "building")
        model = surrogate_for(
            "series", campaign.metamodel, series, space, campaign.sampling.seed, segments
        ).fit(X, y)
        inputs = load_inputs(campaign)
        problem, _ = build_problem(campaign, inputs)
        problem.series_outputs = True
        heat = problem.run({}).heat.sum(axis=1)
        problem.schedule, _ = choose_quiet_hours(campaign, heat, log=lambda line: None)
        evaluator = campaign_evaluator(problem, inputs.building)
        values = {**space.nominal_dict(), **truth}
        true_out = evaluator.outputs(problem.run(values).heat)
        _, true_series, _ = metric_data(pd.DataFrame([true_out]), "building")
    names = list(space.names)
    lin = linear_heat_model(model, names, space.lower, space.upper)
    z_true = np.log(np.array([values[n] for n in names]) / lin.nominal)
    simulated = model.centred(true_series)[0]
    predicted = lin.residual(z_true)  # the meta-model's centred series at the truth
    error = predicted - simulated
    typical = np.sqrt(emulator_variance(model, X, seed=campaign.sampling.seed))
    shift, *_ = np.linalg.lstsq(lin.jacobian, -error, rcond=None)
    # the true envelope's own unoccupied heat is not constant either (the identification's
    # discretisation, the gains of those hours): the shift it causes by itself
    own, *_ = np.linalg.lstsq(lin.jacobian, -simulated, rcond=None)
    post = result.posterior.summary
    print(
        f"\nhours {len(error)}; meta-model error at the truth: RMS "
        f"{np.sqrt(np.mean(error**2)):.1f} W "
        f"against its out-of-fold RMS {typical:.1f} W over the samples"
    )
    print(
        "the true envelope's own centred unoccupied heat: RMS "
        f"{np.sqrt(np.mean(simulated**2)):.1f} W"
    )
    print(
        "| parameter | truth | shift of the best fit by the meta-model's error at the truth "
        "(factor) | by the true envelope's own non-constant heat (factor) | posterior median / "
        "truth | 90 % interval / truth |"
    )
    print("|---|---|---|---|---|---|")
    for i, n in enumerate(names):
        true = values[n]
        print(
            f"| {n} | {true:.4g} | x{np.exp(shift[i]):.3f} | x{np.exp(own[i]):.3f} | "
            f"{post.at[n, 'median'] / true:.3f} | "
            f"{post.at[n, 'q05'] / true:.3f}-{post.at[n, 'q95'] / true:.3f} |"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
