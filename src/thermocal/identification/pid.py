"""Discrete PID controller in controller canonical form, for the heat-balance identification.

The controller of the control-based heat-balance identification (see
:data:`thermocal.identification.REFERENCE`, eq. 4-9) is the discrete PID

.. math::

    H(z) = K_P + K_I \\frac{z}{z - 1} + K_D \\frac{z - 1}{z}
         = \\frac{(K_P + K_I + K_D) + (-K_P - 2 K_D) z^{-1} + K_D z^{-2}}{1 - z^{-1}},

realised in controller canonical form with ``A = [[1, 0], [1, 0]]``, ``B = [1, 0]^T``,
``C = [K_I - K_D, K_D]``, ``D = [K_P + K_I + K_D]`` (eq. 8): the state is
``x1[k] = sum_{i<k} e[i]``, ``x2[k] = x1[k-1]`` and the output
``u[k] = C x[k] + D e[k] = K_P e[k] + K_I sum_{i<=k} e[i] + K_D (e[k] - e[k-1])``.

Gain convention of this module (and of the whole API): **discrete gains**, the coefficients of
H(z) above, all in [W/K] (heat per kelvin of tracking error). The continuous gains of eq. 4
(``K_P`` [W/K], ``K_I`` [W/(K s)], ``K_D`` [W s/K]) map to them through the positional form of
eq. 5 with the sampling time ``t_s`` [s]::

    K_P,discrete = K_P,  K_I,discrete = K_I t_s,  K_D,discrete = K_D / t_s

(:meth:`PIDGains.from_continuous` and :meth:`PIDGains.to_continuous`). The Ziegler-Nichols rule
of eq. 9 gives continuous gains from the ultimate gain and period; :func:`ziegler_nichols`
returns them converted to discrete gains for the given ``t_s``.

References
----------
Calibration of envelope parameters using control-based heat balance identification and
uncertainty analysis, conference paper (:data:`thermocal.identification.REFERENCE`).
Franklin, G. F., Powell, J. D., Emami-Naeini, A. (2006). Feedback Control of Dynamic Systems,
5th ed., Pearson (Ziegler-Nichols ultimate-sensitivity method).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from thermocal.errors import ThermocalInputError


@dataclass(frozen=True)
class PIDGains:
    """Discrete PID gains of H(z) = KP + KI z/(z-1) + KD (z-1)/z.

    Parameters
    ----------
    kp, ki, kd : float [W/K]
        Proportional, integral (per sample) and derivative (per sample) gains.
    """

    kp: float
    ki: float = 0.0
    kd: float = 0.0

    def __post_init__(self) -> None:
        for name in ("kp", "ki", "kd"):
            value = getattr(self, name)
            if not np.isfinite(value) or value < 0:
                raise ThermocalInputError(
                    f"PID gain {name} = {value!r} must be finite and >= 0 [W/K]"
                )

    @classmethod
    def from_continuous(cls, kp: float, ki: float, kd: float, ts: float) -> PIDGains:
        """Discrete gains from the continuous ones of eq. 4 and the sampling time.

        Parameters
        ----------
        kp : float [W/K]
        ki : float [W/(K s)]
        kd : float [W s/K]
        ts : float [s]
            Sampling time (the simulation step).
        """
        if not ts > 0:
            raise ThermocalInputError(f"sampling time ts = {ts!r} s must be > 0")
        return cls(kp, ki * ts, kd / ts)

    def to_continuous(self, ts: float) -> tuple[float, float, float]:
        """Continuous gains ``(KP [W/K], KI [W/(K s)], KD [W s/K])`` for the step ``ts`` [s]."""
        return self.kp, self.ki / ts, self.kd * ts

    def scaled(self, ratio: float) -> PIDGains:
        """All three gains multiplied by ``ratio`` [-] (the paper's volume scaling)."""
        return PIDGains(self.kp * ratio, self.ki * ratio, self.kd * ratio)

    def canonical_form(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Matrices ``(A, B, C, D)`` of the controller canonical realisation (eq. 8)."""
        a = np.array([[1.0, 0.0], [1.0, 0.0]])
        b = np.array([[1.0], [0.0]])
        c = np.array([[self.ki - self.kd, self.kd]])
        d = np.array([[self.kp + self.ki + self.kd]])
        return a, b, c, d

    def transfer_function(self, z: complex | np.ndarray) -> complex | np.ndarray:
        """H(z) [W/K] at the complex frequency ``z``."""
        z = np.asarray(z, dtype=complex)
        return self.kp + self.ki * z / (z - 1.0) + self.kd * (z - 1.0) / z

    def as_dict(self) -> dict[str, float]:
        return {"kp_W_per_K": self.kp, "ki_W_per_K": self.ki, "kd_W_per_K": self.kd}


def kernel_coefficients(gains: list[PIDGains]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per-zone ``(D, C1, C2)`` of the canonical form, as the compiled loop takes them [W/K]."""
    d = np.array([g.kp + g.ki + g.kd for g in gains], dtype=float)
    c1 = np.array([g.ki - g.kd for g in gains], dtype=float)
    c2 = np.array([g.kd for g in gains], dtype=float)
    return d, c1, c2


def canonical_pid_response(errors: np.ndarray, gains: PIDGains) -> np.ndarray:
    """Controller output for an error sequence, by the state-space recursion of eq. 8 [W].

    Parameters
    ----------
    errors : ndarray [K]
        Error ``e[k]`` per sample (starting from a zero state).
    gains : PIDGains
    """
    a, b, c, d = gains.canonical_form()
    x = np.zeros((2, 1))
    out = np.empty(len(errors))
    for k, e in enumerate(np.asarray(errors, dtype=float)):
        out[k] = (c @ x + d * e).item()
        x = a @ x + b * e
    return out


def positional_pid_response(errors: np.ndarray, gains: PIDGains) -> np.ndarray:
    """Controller output by the textbook positional form of eq. 5 [W] (``e[-1] = 0``)."""
    errors = np.asarray(errors, dtype=float)
    previous = np.concatenate([[0.0], errors[:-1]])
    return gains.kp * errors + gains.ki * np.cumsum(errors) + gains.kd * (errors - previous)


def ziegler_nichols(ultimate_gain: float, ultimate_period: float, ts: float) -> PIDGains:
    """PID gains from the ultimate gain and period by the rule of eq. 9, as discrete gains.

    ``KP = Ku / 1.7``, ``KI = 2 Ku / (1.7 Pu)``, ``KD = Ku Pu / (1.7 x 8)`` (continuous), then
    converted with the sampling time (module docstring).

    Parameters
    ----------
    ultimate_gain : float [W/K]
    ultimate_period : float [s]
    ts : float [s]
        Sampling time.
    """
    if not ultimate_gain > 0 or not ultimate_period > 0:
        raise ThermocalInputError(
            f"Ziegler-Nichols needs a positive ultimate gain and period, got Ku = "
            f"{ultimate_gain!r} W/K, Pu = {ultimate_period!r} s"
        )
    kp = ultimate_gain / 1.7
    ki = 2.0 * ultimate_gain / (1.7 * ultimate_period)
    kd = ultimate_gain * ultimate_period / (1.7 * 8.0)
    return PIDGains.from_continuous(kp, ki, kd, ts)
