"""The demo generators moved to ``thermocal.demos`` (issue 23): the old paths still work."""

from __future__ import annotations

import subprocess
import sys
import warnings

import pytest

import thermocal.demos.buildings as buildings
import thermocal.demos.identification as identification
import thermocal.demos.retrofit as retrofit

OLD = {
    "thermocal.multizone.generators": buildings,
    "thermocal.retrofit.demo_data": retrofit,
    "thermocal.identification.demo_data": identification,
}


def _old(name: str):
    import importlib

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        return importlib.import_module(name)


@pytest.mark.parametrize("old_name", sorted(OLD))
def test_old_module_hands_on_the_same_objects(old_name):
    old, new = _old(old_name), OLD[old_name]
    names = [n for n in vars(new) if not (n.startswith("__") and n.endswith("__"))]
    assert names
    for name in names:  # public and private names alike
        assert getattr(old, name) is getattr(new, name), name
    with pytest.raises(AttributeError):
        old.no_such_name  # noqa: B018


def test_named_examples():
    from thermocal import multizone

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        from thermocal.identification.demo_data import _rows, load_demo
        from thermocal.multizone.generators import Room, clinic, plan_building
        from thermocal.retrofit.demo_data import SHIPPED_DATA, generate_demo_data

        assert multizone.generators.single_family_house is buildings.single_family_house
    assert clinic is buildings.clinic and Room is buildings.Room
    assert plan_building is buildings.plan_building
    assert load_demo is identification.load_demo and _rows is identification._rows
    assert generate_demo_data is retrofit.generate_demo_data
    assert SHIPPED_DATA == retrofit.SHIPPED_DATA and SHIPPED_DATA.is_dir()
    assert identification.DEMO_FOLDER.is_dir()


def test_old_paths_warn_and_the_old_command_runs():
    script = "import " + ", ".join(sorted(OLD))
    done = subprocess.run([sys.executable, "-W", "always::DeprecationWarning", "-c", script],
                          capture_output=True, text=True, timeout=300)  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]
    for old_name, new in OLD.items():
        assert f"{old_name} moved to {new.__name__}" in done.stderr
    # python -m thermocal.identification.demo_data forwards to the new generator's main()
    done = subprocess.run(
        [sys.executable, "-m", "thermocal.identification.demo_data", "--help"],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]
    assert "python -m thermocal.demos.identification" in done.stdout
    assert "moved to thermocal.demos.identification" in done.stderr
