"""Brute-force references for the statespace tests: the joint Gaussian of all states and outputs."""

from __future__ import annotations

import numpy as np
from scipy import stats

from thermocal.statespace import RCModel
from thermocal.statespace.data import prepare_data
from thermocal.statespace.discretise import discretise


def dense_moments(model: RCModel, df, hold: str = "zoh", params=None):
    """Mean and covariance of all states (N n) and all outputs (N ny), by brute force."""
    prep = prepare_data(model, df)
    A, B, C, _ = model.continuous_matrices(params)
    Sigma = model.diffusion_matrix(params)
    values = model.values_si(params)
    st = model.structure()
    x0 = values[st.arrays[16]]
    P0 = np.diag(values[st.arrays[17]] ** 2)
    R = np.diag(values[st.arrays[15]] ** 2)
    N, n = len(df), A.shape[0]
    mean = np.zeros((N, n))
    cov = np.zeros((N * n, N * n))
    mean[0] = x0
    cov[:n, :n] = P0
    for k in range(N - 1):
        Ad, G0, G1, Q = discretise(A, B, Sigma, prep.dts[k], hold)
        mean[k + 1] = Ad @ mean[k] + G0 @ prep.U[k] + G1 @ prep.U[k + 1]
        sl = slice(k * n, (k + 1) * n)
        nx = slice((k + 1) * n, (k + 2) * n)
        cov[nx, : (k + 1) * n] = Ad @ cov[sl, : (k + 1) * n]
        cov[: (k + 1) * n, nx] = cov[nx, : (k + 1) * n].T
        cov[nx, nx] = Ad @ cov[sl, sl] @ Ad.T + Q
    Cbig = np.kron(np.eye(N), C)
    ycov = Cbig @ cov @ Cbig.T + np.kron(np.eye(N), R)
    xycov = cov @ Cbig.T
    return prep, mean.ravel(), cov, (mean @ C.T).ravel(), ycov, xycov


def dense_loglike(model: RCModel, df, hold: str) -> float:
    """Exact Gaussian log-likelihood from the full covariance matrix of all observations."""
    prep, _, _, ymean, ycov, _ = dense_moments(model, df, hold)
    y = prep.Y.ravel()
    obs = np.isfinite(y)
    return stats.multivariate_normal(ymean[obs], ycov[np.ix_(obs, obs)]).logpdf(y[obs])
