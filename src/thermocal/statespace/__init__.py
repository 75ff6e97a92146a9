"""Grey-box estimation engine: continuous-time stochastic RC models fitted by maximum likelihood.

Public API
----------
RCModel
    Declaration of an RC network (states, conductances, heat inputs, outputs, noise, parameters),
    from a YAML model file, a dictionary or step by step; ``fit``, ``simulate``, ``loglike``,
    ``continuous_matrices``.
FitResults
    Estimates, standard errors, correlation, log-likelihood, AIC/BIC, flags, predictions,
    residuals, smoothing, summary and ``to_dict`` (fit.json).
"""

from thermocal.statespace.data import PreparedData, prepare_data
from thermocal.statespace.model import Parameter, RCModel
from thermocal.statespace.results import FitResults

__all__ = ["FitResults", "Parameter", "PreparedData", "RCModel", "prepare_data"]
