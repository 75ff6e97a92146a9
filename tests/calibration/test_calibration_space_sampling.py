"""Parameter space and sampling: bounds, clipping counts, reproducibility, name errors."""

from __future__ import annotations

import numpy as np
import pytest

from thermocal.calibration.sampling import sample, unit_sample
from thermocal.calibration.space import ParameterSpace, parameter_unit
from thermocal.errors import ThermocalInputError

PARAMS = {
    "material/brick/conductivity": 0.8,
    "material/brick/density": 1800.0,
    "material/brick/thickness": 0.2,
    "material/airgap/resistance": 0.18,
    "window/double/u_value": 2.8,
    "window/double/shgc": 0.6,
    "zone/office/infiltration_ach": 0.5,
    "infiltration/north/ach": 0.3,
}
PAPER_RANGES = {"*/shgc": 100.0, "*/thickness": 10.0}


def test_default_range_and_overrides():
    space = ParameterSpace.from_parameters(PARAMS, ranges=PAPER_RANGES)
    frame = space.to_frame()
    assert frame.loc["material/brick/conductivity", "range_lower"] == pytest.approx(0.2)
    assert frame.loc["material/brick/conductivity", "range_upper"] == pytest.approx(1.4)
    assert frame.loc["window/double/shgc", "range_lower"] == pytest.approx(0.6 * -99)
    assert frame.loc["material/brick/thickness", "range_upper"] == pytest.approx(2.2)
    # effective bounds clipped to the physical limits: 1 % of nominal, 1 for a fraction
    assert frame.loc["window/double/shgc", "lower"] == pytest.approx(0.006)
    assert frame.loc["window/double/shgc", "upper"] == pytest.approx(1.0, abs=1e-8)  # a hair in
    assert frame.loc["material/brick/thickness", "lower"] == pytest.approx(0.002)
    assert set(space.clipped) == {"window/double/shgc", "material/brick/thickness"}
    assert parameter_unit("material/brick/conductivity") == "W/(m K)"
    assert frame.loc["infiltration/north/ach", "unit"] == "1/h"


def test_samples_respect_limits_and_clip_counts_are_exact():
    space = ParameterSpace.from_parameters(PARAMS, ranges=PAPER_RANGES)
    for method in ("sobol", "lhs", "halton"):
        s = sample(space, 200, method, seed=3)
        v = s.values.to_numpy()
        assert v.shape == (200, len(space))
        assert np.all(v >= space.limit_lower) and np.all(v <= space.limit_upper)
        assert np.all(v >= space.lower - 1e-15) and np.all(v <= space.upper + 1e-15)
        # recount the clips from the unclipped points
        raw = space.scale(unit_sample(len(space), 200, method=method, seed=3))
        lower = (raw < space.limit_lower).sum(axis=0)
        upper = (raw > space.limit_upper).sum(axis=0)
        assert np.array_equal(s.clip_counts["lower"].to_numpy(), lower)
        assert np.array_equal(s.clip_counts["upper"].to_numpy(), upper)
        # values on the limits are exactly the clipped ones
        assert np.array_equal((v == space.limit_lower).sum(axis=0), lower)
        # unclipped parameters (+-75 %) never clip; shgc +-10000 % clips ~99 % of samples
        assert s.clip_counts.loc["material/brick/conductivity", "total"] == 0
        assert s.clip_counts.loc["window/double/shgc", "fraction"] > 0.95
        # thickness +-1000 %: the part below 1 % of nominal is (0.2 * 9.01)/(0.2 * 20) = 45 %
        assert s.clip_counts.loc["material/brick/thickness", "fraction"] == pytest.approx(
            0.4505, abs=0.03)


def test_sampling_is_reproducible_with_the_seed():
    space = ParameterSpace.from_parameters(PARAMS)
    a = sample(space, 50, "sobol", seed=7).values
    b = sample(space, 50, "sobol", seed=7).values
    c = sample(space, 50, "sobol", seed=8).values
    assert a.equals(b)
    assert not a.equals(c)
    # the first points of a longer Sobol' design are the shorter design
    assert np.array_equal(sample(space, 64, seed=7).values.to_numpy()[:50], a.to_numpy())
    assert list(a.columns) == list(space.names)


def test_include_exclude_selection():
    space = ParameterSpace.from_parameters(PARAMS, include=["material/*", "window/*"],
                                           exclude=["*/density"])
    assert "material/brick/density" not in space.names
    assert "zone/office/infiltration_ach" not in space.names
    assert "window/double/shgc" in space.names


@pytest.mark.parametrize(
    ("kwargs", "expected"),
    [
        ({"include": ["materail/*"]}, "did you mean 'material/*'"),
        ({"exclude": ["window/dubble/*"]}, "did you mean 'window/double/*'"),
        ({"ranges": {"*/shgcc": 1.0}}, "did you mean '*/shgc'"),
        ({"ranges": {"*/thikness": 1.0}}, "did you mean '*/thickness'"),
    ],
)
def test_unknown_patterns_say_did_you_mean(kwargs, expected):
    with pytest.raises(ThermocalInputError, match="matches no model parameter") as info:
        ParameterSpace.from_parameters(PARAMS, **kwargs)
    assert expected in str(info.value)


def test_bad_ranges_and_counts():
    with pytest.raises(ThermocalInputError, match="non-negative"):
        ParameterSpace.from_parameters(PARAMS, default_range=-0.1)
    with pytest.raises(ThermocalInputError, match=r"ranges\['\*/shgc'\]"):
        ParameterSpace.from_parameters(PARAMS, ranges={"*/shgc": -1})
    space = ParameterSpace.from_parameters(PARAMS)
    for n in (0, -5, 2.5):
        with pytest.raises(ThermocalInputError, match="samples"):
            sample(space, n)
    with pytest.raises(ThermocalInputError, match="unknown"):
        sample(space, 10, "random")


def test_zero_nominal_is_skipped_and_negative_rejected():
    space = ParameterSpace.from_parameters({**PARAMS, "zone/attic/infiltration_ach": 0.0})
    assert "zone/attic/infiltration_ach" in space.skipped
    assert "zone/attic/infiltration_ach" not in space.names
    with pytest.raises(ThermocalInputError, match="'material/x/density'"):
        ParameterSpace.from_parameters({"material/x/density": -1.0})


def test_parameters_the_model_does_not_use_are_left_out_with_the_reason():
    unused = {"material/airgap/resistance": "material 'airgap' is in no construction"}
    space = ParameterSpace.from_parameters(PARAMS, unused=unused)
    assert "material/airgap/resistance" not in space.names
    assert space.skipped["material/airgap/resistance"] == (
        "not used by the model: material 'airgap' is in no construction"
    )
    assert len(space) == len(PARAMS) - 1
    with pytest.raises(ThermocalInputError, match=r"left out: material/airgap/resistance: not"):
        ParameterSpace.from_parameters(PARAMS, include=["material/airgap/*"], unused=unused)
    from thermocal.calibration.workflow import left_out_notes

    lines = []
    notes = left_out_notes(space, lines.append)
    assert notes == [
        "Parameters left out of the campaign: material/airgap/resistance (not used by the "
        "model: material 'airgap' is in no construction)."
    ]
    assert lines and "material/airgap/resistance" in lines[0]
    assert left_out_notes(ParameterSpace.from_parameters(PARAMS), lines.append) == []


def test_real_building_parameters():
    from thermocal.demos import buildings as generators

    building = generators.single_family_house() if hasattr(
        generators, "single_family_house") else None
    if building is None:
        pytest.skip("no generator")
    params = building.parameters()
    space = ParameterSpace.from_parameters(params, ranges=PAPER_RANGES)
    assert len(space) + len(space.skipped) == len(params)
    s = sample(space, 32, seed=1)
    assert np.isfinite(s.values.to_numpy()).all()
    # the sampled values are accepted by the model
    building.with_parameters(s.values.iloc[0].to_dict())


def _model_refusals(building, space, n: int = 64) -> list[str]:
    """Messages of the samples the building model refuses (should be none)."""
    s = sample(space, n, seed=3)
    refused = []
    for _, row in s.values.iterrows():
        try:
            building.with_parameters(row.to_dict())
        except ThermocalInputError as exc:
            refused.append(str(exc))
    return refused


@pytest.mark.parametrize("relative_range", [0.75, 0.99])
def test_every_sample_of_a_valid_space_is_a_valid_building(relative_range):
    """The limits of sampling and model have one source: no sample is refused by the model
    (before: light insulation densities sampled below the model's 5 kg/m3 failed the run)."""
    from thermocal.demos import buildings as generators
    from thermocal.multizone.model import Material

    building = generators.single_family_house()
    space = ParameterSpace.from_parameters(building.parameters(), default_range=relative_range)
    assert _model_refusals(building, space) == []
    light = [n for n, m in building.materials.items()
             if isinstance(m, Material) and m.density * (1 - relative_range) < 5.0]
    for name in light:
        i = space.index(f"material/{name}/density")
        assert space.lower[i] == pytest.approx(5.0)  # the model's plausible minimum


def test_every_sample_of_an_energyplus_building_is_valid(shared_data):
    """NREL's 5ZoneAirCooled (an IDF thermocal did not write) over material, window and
    infiltration parameters at +-75 %: 22 of 128 samples were refused before."""
    import warnings

    from thermocal.multizone.idf import read_idf

    idf = shared_data("energyplus_reference", "5ZoneAirCooled_FF_v25.idf")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = read_idf(idf)
    from thermocal.multizone.elements import window_limits

    space = ParameterSpace.from_parameters(
        building.parameters(),
        include=["material/*", "window/*", "*/infiltration_ach"],
        limits=window_limits(building),  # as campaign_space gives them
    )
    assert _model_refusals(building, space, n=128) == []


def test_a_value_on_a_model_limit_survives_a_round_trip_through_logarithms():
    """A posterior median or an optimum on the window U-value's limit (10 W/(m2 K)) is computed
    as nominal * exp(log(limit / nominal)); before, it came back 10.000000000000002 and the
    model refused the calibrated building at the very end of a campaign."""
    rng = np.random.default_rng(3)
    for nominal in rng.uniform(0.8, 6.0, 2000):
        space = ParameterSpace.from_parameters({"window/w/u_value": nominal}, default_range=1.0)
        upper = space.upper[0]
        assert upper <= 10.0
        assert nominal * np.exp(np.log(upper / nominal)) <= 10.0
        assert np.exp(np.log(upper)) <= 10.0


def test_a_campaign_samples_a_layered_windows_shgc_only_as_far_as_its_glazing_reaches(shared_data):
    """5ZoneAirCooled's double glazing (SHGC 0.764) can reach 0.875: a campaign's SHGC range
    (+-75 %, and the published +-10000 %) stops there at both parameter levels, so no sample is
    simulated at another SHGC than it is stored with (before, up to 1 was sampled)."""
    from types import SimpleNamespace

    from thermocal.calibration.config import ParametersSection
    from thermocal.calibration.workflow import campaign_space
    from thermocal.multizone.idf import read_idf

    building = read_idf(shared_data("energyplus_reference", "5ZoneAirCooled_FF_v25.idf"))
    name = "Dbl Clr 3mm/13mm Air"
    limit = building.window_types[name].shgc_limit
    assert 0.8 < limit < 0.9
    for level in ("material", "element"):
        for ranges in ({}, {"*/shgc": 100.0}):
            section = ParametersSection(level=level, include=["window/*"], ranges=ranges)
            space = campaign_space(SimpleNamespace(parameters=section), building)
            i = space.index(f"window/{name}/shgc")
            assert space.upper[i] == pytest.approx(limit, rel=1e-8)
            building.with_parameters({f"window/{name}/shgc": float(space.upper[i])})
