"""The sensor-log reader's remedies name its Python options (``tz=``, ``sort=True``, ...);
each command says them in its own terms (options or configuration keys). These tests run the
reader on the faulty logs and check that no Python wording reaches a command's user: they fail
when the reader's wording drifts from the commands' tables."""

from __future__ import annotations

import re

import pytest

from thermocal.errors import ThermocalInputError
from thermocal.io.measurements import read_measurements

LOGS = {
    "naive times": "time,T\n2021-01-04 00:00,20.0\n2021-01-04 00:10,20.1\n",
    "duplicated time": "time,T\n2021-01-04T00:00Z,20.0\n2021-01-04T00:00Z,20.1\n",
    "unsorted": "time,T\n2021-01-04T00:10Z,20.0\n2021-01-04T00:00Z,20.1\n",
    "numeric times": "time,T\n1609718400,20.0\n1609719000,20.1\n",
    "decimal comma": "time;T\n2021-01-04T00:00Z;20,5\n2021-01-04T00:10Z;20,6\n",
}
PYTHON = re.compile(r"\b(tz|sort|duplicates|time_unit|start|decimal|interval)=|in Python")


def _message(tmp_path, name: str) -> str:
    path = tmp_path / "log.csv"
    path.write_text(LOGS[name])
    with pytest.raises(ThermocalInputError) as info:
        read_measurements(path, quantities={"T": "temperature"})
    return str(info.value)


@pytest.mark.parametrize("name", sorted(LOGS))
def test_identify_names_its_options(tmp_path, name):
    from thermocal.commands.identify import _READER_REMEDIES

    text = _message(tmp_path, name)
    assert PYTHON.search(text), text  # the reader's own wording, which the table must cover
    for option, remedy in _READER_REMEDIES:
        text = text.replace(option, remedy)
    assert not PYTHON.search(text), text


@pytest.mark.parametrize("name", sorted(LOGS))
def test_retrofit_names_its_configuration_keys(tmp_path, name):
    from thermocal.retrofit.data import _NUMERIC_TIMES, _READER_REMEDIES

    text = _message(tmp_path, name)
    for option, remedy in _READER_REMEDIES:
        text = text.replace(option, remedy)
    text = _NUMERIC_TIMES.sub(r"\1; write dates", text)
    assert not PYTHON.search(text), text
    assert "--" not in text, text  # no command-line option either
