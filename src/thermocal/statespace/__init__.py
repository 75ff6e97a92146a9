"""Grey-box estimation engine: continuous-time stochastic RC models fitted by maximum likelihood.

Declare an RC network (:class:`RCModel`, from a YAML model file, a dictionary or step by step),
fit it to data with a Kalman-filter likelihood (:meth:`RCModel.fit`), and inspect the
:class:`FitResults` (estimates, standard errors, correlation, flags, residual diagnostics,
k-step prediction, RTS smoothing, deterministic simulation). Nested models are compared with
:func:`likelihood_ratio_test`; :func:`forward_selection` extends a model while the test says so
(Bacher & Madsen 2011). The file format is documented in ``docs/model-file.md``.

References
----------
.. [1] N. R. Kristensen, H. Madsen, S. B. Jorgensen, "Parameter estimation in stochastic grey-box
   models", Automatica 40(2), 225-237, 2004.
.. [2] P. Bacher, H. Madsen, "Identifying suitable models for the heat dynamics of buildings",
   Energy and Buildings 43(7), 1511-1522, 2011.
"""

from thermocal.statespace.data import PreparedData, prepare_data, time_axis
from thermocal.statespace.diagnostics import (
    LikelihoodRatioTest,
    autocorrelation,
    cumulated_periodogram,
    fraction_outside_band,
    likelihood_ratio_test,
)
from thermocal.statespace.discretise import discretise
from thermocal.statespace.estimation import evaluate
from thermocal.statespace.kalman import simulate_stochastic
from thermocal.statespace.model import Parameter, RCModel
from thermocal.statespace.results import FitResults
from thermocal.statespace.selection import SelectionResult, forward_selection

__all__ = [
    "FitResults",
    "LikelihoodRatioTest",
    "Parameter",
    "PreparedData",
    "RCModel",
    "SelectionResult",
    "autocorrelation",
    "cumulated_periodogram",
    "discretise",
    "evaluate",
    "forward_selection",
    "fraction_outside_band",
    "likelihood_ratio_test",
    "prepare_data",
    "simulate_stochastic",
    "time_axis",
]
