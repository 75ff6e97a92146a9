"""State-exchange starts: optimiser starts that let two hidden states swap roles.

The likelihood of an RC network with two unobserved states hanging off the same node (an
internal mass ``Tm`` and an envelope ``Te`` both connected to the indoor air ``Ti``) often has
two optima where the states exchange roles: one state takes the large capacity and the
diffusion noise, the other the small capacity and none (Bacher-Madsen TiTmTeTh on the PRBS data:
``Cm`` 0.43 / ``Ce`` 3.47 kWh/K at log-likelihood 5445.78 against ``Cm`` 2.17 / ``Ce`` 0.58 at
5448.33). A gradient method started in one basin stays there, and random starts around declared
values can all fall into the same one, so that they agree on the poorer optimum. An exchange
start takes an optimiser end and swaps the two states' capacities, noise, initial means and
their resistances (conductances) to the shared node; polished, it lands in the other basin.
"""

from __future__ import annotations

import numpy as np


def _parameter(model, spec) -> str | None:
    """The free parameter named by a state's or a path's ``spec`` entry, else None."""
    if isinstance(spec, str) and spec in model.parameters and not model.parameters[spec].fixed:
        return spec
    return None


def _path_parameter(model, path: dict) -> tuple[str, str] | None:
    """(kind, parameter) of a heat path given by one free resistance or conductance."""
    for kind in ("resistance", "conductance"):
        name = _parameter(model, path.get(kind))
        if name is not None:
            return kind, name
    return None


def _neighbours(model, state: str) -> dict[str, tuple[str, str]]:
    """{node: (kind, parameter)} of the single-parameter heat paths from ``state``."""
    out = {}
    for path in model._conductances:
        a, b = path["between"]
        if state not in (a, b):
            continue
        other = b if a == state else a
        spec = _path_parameter(model, path)
        if spec is not None:
            out[other] = spec
    return out


def _heated(model) -> set[str]:
    """States into which a heat-input column flows."""
    heated = set()
    for spec in model._heat_inputs:
        into = spec["into"]
        heated |= {into} if isinstance(into, str) else set(into)
    return heated


def exchange_pairs(model) -> list[list[tuple[str, str]]]:
    """The parameter swaps of each pair of states that can exchange roles.

    A pair qualifies when both states are unobserved (no output row of ``C`` sees them), receive
    no heat input, have free capacity parameters of the same unit and share a node connected to
    each by one free resistance (or conductance). The swap covers the capacities, the diffusion
    noises, the initial means (when both are free parameters of the same unit) and the two paths
    to each shared node.

    Returns
    -------
    list of list of (str, str)
        Per pair, the parameter names whose values are exchanged.
    """
    st = model.structure()
    observed = {model.state_names[j] for j in np.flatnonzero(np.any(st.C != 0.0, axis=0))}
    heated = _heated(model)
    states = [s for s in model.state_names if s not in observed and s not in heated]
    pairs = []
    for i, a in enumerate(states):
        for b in states[i + 1 :]:
            swaps = []
            for key in ("capacity", "noise", "initial_mean"):
                pa = _parameter(model, model._states[a].get(key))
                pb = _parameter(model, model._states[b].get(key))
                if pa and pb and model.parameters[pa].unit == model.parameters[pb].unit:
                    swaps.append((pa, pb))
            if not swaps or swaps[0][0] != _parameter(model, model._states[a]["capacity"]):
                continue  # the capacities must be exchangeable
            na, nb = _neighbours(model, a), _neighbours(model, b)
            shared = [(na[n], nb[n]) for n in na if n in nb and na[n][0] == nb[n][0]]
            if not shared:
                continue
            swaps += [(pa, pb) for (_, pa), (_, pb) in shared if pa != pb]
            pairs.append(swaps)
    return pairs


def exchanged_values(values: dict[str, float], swaps) -> dict[str, float]:
    """``values`` [declared units] with the values of each pair of ``swaps`` exchanged."""
    out = dict(values)
    for a, b in swaps:
        out[a], out[b] = values[b], values[a]
    return out
