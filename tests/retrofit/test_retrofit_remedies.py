"""Every remedy a flag of the grey-box engine offers can be followed from the retrofit
configuration (issue 25 item 4).

The engine's flags (``thermocal.statespace.results``) name its own options: model files,
``--n-starts``, ``heat_inputs`` column declarations, start values. The retrofit workflow passes
each flag through :func:`thermocal.retrofit.calibration.retrofit_remedy`, which must leave no
such option behind. The flags are taken from the engine's source (every message literal that
offers a remedy, its formatted values as ``{}``), so a new engine flag is checked too.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import thermocal.statespace.results as engine_results
from thermocal.retrofit.calibration import retrofit_remedy

#: Options of the engine that the retrofit configuration does not have.
ENGINE_ONLY = (
    "--n-starts", "heat_inputs", "stall_tolerance", "simplify the model", "simpler model",
    "give it a prior", "merge it with", "models are nested", "allow_negative",
    "start values closer", "or from there", "remove parameters",
)  # fmt: skip
#: What a flag says when it offers something to do.
OFFERS = ("remedy:", "fix one of them", "fix or remove", "widen the bound")


def _text(node) -> str:
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return node.value
    if isinstance(node, ast.JoinedStr):
        return "".join(v.value if isinstance(v, ast.Constant) else "{}" for v in node.values)
    return ""


def _engine_flags() -> list[str]:
    """The message literals of the engine's flags that offer a remedy (an f-string and the
    literals it is concatenated with, formatted values as ``{}``)."""
    tree = ast.parse(Path(engine_results.__file__).read_text())
    parts = {id(v) for n in ast.walk(tree) if isinstance(n, ast.JoinedStr) for v in n.values}
    out = []
    for node in ast.walk(tree):
        if id(node) in parts:  # a piece of an f-string: the whole is taken
            continue
        text = _text(node)
        if any(o in text for o in OFFERS):
            out.append(text)
    return out


def test_the_engine_offers_remedies():
    flags = _engine_flags()
    assert len(flags) >= 10, flags  # (13 in the engine of 2026-11-28)


@pytest.mark.parametrize("flag", _engine_flags(), ids=lambda f: f[:40])
def test_every_engine_remedy_is_a_retrofit_configuration_key(flag):
    """Before 2026-11-28 seven of them kept an engine option: start values, 'from there',
    nested models, 'fix one of them' / 'fix or remove parameters' without a key, 'widen the
    bound ... simplify the model', and 'allow_negative: true' in heat_inputs."""
    text = retrofit_remedy(flag)
    left = [e for e in ENGINE_ONLY if e in text]
    assert not left, (left, text)
    if "fix" in text and "fix the meter" not in text:
        assert "model.fixed" in text, text


def test_a_finer_step_is_offered_down_to_the_log_interval_only():
    """Non-white residuals: before, 'use a finer step (measurements.step)' on a grid already
    at the log's interval, where a finer step is refused (it only holds each logged value)."""
    import pandas as pd

    flag = next(f for f in _engine_flags() if "finer model of the heating" in f)
    hour, ten = pd.Timedelta("1h"), pd.Timedelta("10min")
    at_log = retrofit_remedy(flag, step=hour, log_interval=hour)
    assert "finer step" not in at_log and at_log.endswith("or check the heating data"), at_log
    coarser = retrofit_remedy(flag, step=hour, log_interval=ten)
    assert coarser.endswith(
        "or use a finer step (measurements.step, now 1h), down to the log's interval of 10min"
    ), coarser
    assert retrofit_remedy(flag).endswith(
        "use a finer step (measurements.step), down to the log's interval"
    )
