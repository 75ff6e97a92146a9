"""Retrofit analysis with the fifth-order RC method: the model, calibration, validation, annual
heating demand, retrofit strategies (default: the method's 16) with uncertainty, economics.

Public API
----------
load_config(path) -> RetrofitConfig, parse_config(mapping, base_dir=...)
run_retrofit(config, progress=None) -> RetrofitAnalysis
write_outputs(analysis, out_dir, true_hlc=None) -> dict (results.json content)
build_fifth_order_model(building, solar_to_internal_mass=0.5) -> FifthOrderModel
all_strategies() -> list[Strategy]; PAPER_MEASURE_U_VALUES
validation_metrics(simulated, measured) -> dict
simulate_demand(model, params_si, envelopes, inputs, profile) -> DemandResult
"""

from thermocal.retrofit.config import RetrofitConfig, load_config, parse_config
from thermocal.retrofit.demand import DemandResult, simulate_demand, steady_state_demand
from thermocal.retrofit.metrics import validation_metrics
from thermocal.retrofit.model import FifthOrderModel, build_fifth_order_model
from thermocal.retrofit.strategies import PAPER_MEASURE_U_VALUES, Strategy, all_strategies


def run_retrofit(config, *, progress=None):
    """Run the retrofit workflow (see :func:`thermocal.retrofit.workflow.run_retrofit`)."""
    from thermocal.retrofit.workflow import run_retrofit as _run

    return _run(config, progress=progress)


def write_outputs(analysis, out_dir, **options):
    """Write results.json, CSV, figures, report.html (see :mod:`thermocal.retrofit.outputs`)."""
    from thermocal.retrofit.outputs import write_outputs as _write

    return _write(analysis, out_dir, **options)


__all__ = [
    "PAPER_MEASURE_U_VALUES",
    "DemandResult",
    "FifthOrderModel",
    "RetrofitConfig",
    "Strategy",
    "all_strategies",
    "build_fifth_order_model",
    "load_config",
    "parse_config",
    "run_retrofit",
    "simulate_demand",
    "steady_state_demand",
    "validation_metrics",
    "write_outputs",
]
