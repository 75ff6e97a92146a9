"""The two-dimensional ground section under a floor on EnergyPlus's Foundation boundary (Kiva).

Truth we did not make: EnergyPlus 25.2's Kiva on NREL's SingleFamilyHouse
(``tests/reference/retrofit_energyplus_house``, ``make_reference.py --ground``:
``ground_study.json``), the slab's steady heat loss coefficient at Kiva's own soil (no settings
object: 0.864 W/(m K)) and at 2.0 W/(m K), without and with 12.2 cm of insulation under the slab
(U 0.25); the whole house's steady heat loss coefficient (``reference.json``, 299.2 W/K).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from conftest import load_script
from thermocal.errors import ThermocalInputError
from thermocal.multizone.foundation import (
    KIVA_DEFAULT_SOIL,
    FoundationGround,
    foundation_grid,
    steady_floor_conductance,
)

REF = Path(__file__).resolve().parents[1] / "reference" / "retrofit_energyplus_house"
#: The house's foundation wall (EXTWALL:GARAGE, inside first) and floor (outside first).
WALL = ((0.2032, 1.048, 1105.0, 837.0), (0.0254, 0.6918, 1858.1, 836.8))
FLOOR = [(0.1016, 1.31, 2243.0, 837.0), (0.0127, 0.0585, 200.0, 1300.0)]
INSULATED = [(0.122, 0.035, 30.0, 1450.0), *FLOOR]
AREA, PERIMETER = 185.8, 49.121


def _kiva() -> dict:
    return json.loads((REF / "ground_study.json").read_text())["floor_W_per_K_steady"]


@pytest.mark.parametrize(
    ("soil", "floor", "case", "measured"),
    [
        (0.864, FLOOR, "steady_soil173", 61.4),
        (0.864, INSULATED, "steady_soil173_slab", 39.8),
        (2.0, FLOOR, "steady_soil2", 105.1),
        (2.0, INSULATED, "steady_soil2_slab", 48.4),
    ],
)
def test_steady_slab_against_kiva(soil, floor, case, measured):
    """The slab's steady conductance from the room's air within 20 % of Kiva's (measured
    2026-11-30, the grade's convection at EnergyPlus's 3 m/s: 61.4 vs 61.9, 39.8 vs 46.1, 105.1
    vs 94.1, 48.4 vs 52.9 W/K; ISO 13370 gives 47.1, 23.4, 89.0 and 31.8: it has no slab edge on
    the foundation wall). ``steady_soil173`` is the reference run without a settings object,
    i.e. at Kiva's own 0.864 W/(m K). Caution: thermocal's number has ISO 6946's floor film
    (0.17 m2 K/W), EnergyPlus's its own, much weaker one (heat flowing down): below the floor's
    surface EnergyPlus reports 22 % more than the section (next test: floor conduction that no
    ground path carries), so the agreement here is partly the films'."""
    ground = FoundationGround(PERIMETER, soil=(soil, 1510.0, 1260.0), wall_layers=WALL)
    value = steady_floor_conductance(ground, AREA, floor)
    assert value == pytest.approx(_kiva()[case], rel=0.20)
    assert value == pytest.approx(measured, rel=0.02)


@pytest.mark.xfail(
    strict=True,
    reason="measured 2026-11-30: below the living floor's surface thermocal's section conducts "
    "65.0 W/K (70.7 without the carpet) where EnergyPlus's Kiva reports 83.8 (92.1). Not the "
    "section: an independent Kiva-like 2-D solution gives 60.8 (73.3), next test. EnergyPlus "
    "reports 27-31 W/K of floor conduction that no ground path carries: with soil of 0.01 "
    "W/(m K) and an insulating footing wall (0.95 W/K left) it still reports 28.0 W/K "
    "(kiva_variants_study.py -> kiva_variants.json), with or without the carpet",
)
@pytest.mark.parametrize(
    ("floor", "case"), [(FLOOR, "with_carpet"), (FLOOR[:1], "without_carpet")]
)
def test_the_section_below_the_floor_surface_against_kiva(floor, case):
    """The living floor and its ground from the floor's surface to the outdoor air, at steady
    state, against EnergyPlus's Kiva (``floor_surface_study.py`` -> ``floor_surface.json``:
    the house at 20 C over a year of constant 0 C, the floor's inside-face conduction over its
    face temperature), within 10 %: what the section must give below the room's film."""
    kiva = json.loads((REF / "floor_surface.json").read_text())[case]["below_surface_W_per_K"]
    ground = FoundationGround(PERIMETER, soil=KIVA_DEFAULT_SOIL, wall_layers=WALL)
    value = steady_floor_conductance(ground, AREA, floor, inside_resistance=1e-9)
    assert value == pytest.approx(kiva, rel=0.10)


@pytest.mark.parametrize(
    ("soil", "floor"),
    [(0.864, FLOOR), (0.864, FLOOR[:1]), (0.864, INSULATED), (2.0, FLOOR), (2.0, INSULATED)],
)
def test_the_section_against_an_independent_kiva_like_solution(soil, floor):
    """Below the floor's surface, thermocal's section (the slab a 1-D chain with a fin at its
    edge) within 10 % of an independent steady finite-volume solution of Kiva's section as
    Kiva's ``Foundation.cpp`` builds it (the slab meshed in 2-D with the soil and the footing
    wall; ``diagnose_floor_section.py``, checked against ISO 13370 by the next test). It
    shares the mesh spacing and the grade's outdoor coefficient with thermocal's section, not
    the slab's treatment. Measured 2026-11-30: +6.9, -3.6, +4.4, +7.8 and +2.8 %."""
    section = load_script(REF / "diagnose_floor_section.py")
    independent = section.kiva_section(floor, soil_k=soil)
    ground = FoundationGround(PERIMETER, soil=(soil, 1510.0, 1260.0), wall_layers=WALL)
    value = steady_floor_conductance(ground, AREA, floor, inside_resistance=1e-9)
    assert value == pytest.approx(independent, rel=0.10)


def test_the_independent_section_meets_iso_13370_without_a_slab():
    """The independent solution of the previous test in the limit ISO 13370's slab formula
    describes (a floor of negligible thickness at the grade, its surface isothermal): within
    3 % of the standard's ``2 lambda A / (pi B' + d_t) ln(pi B' / d_t + 1)`` with ``B' = 2 A /
    P`` and ``d_t = w + lambda R_se`` (ISO 13370:2017, eq. for ``d_t < B'``; R_se 0.04 m2 K/W,
    no inside film nor floor). Measured 2026-11-30: 59.8 against 60.3 W/K."""
    section = load_script(REF / "diagnose_floor_section.py")
    soil = KIVA_DEFAULT_SOIL[0]
    thin_floor = [(1e-3, soil, 1510.0, 1260.0)]
    independent = section.kiva_section(thin_floor, soil_k=soil, height=1e-3)
    b_prime = 2.0 * AREA / PERIMETER
    d_t = sum(layer[0] for layer in WALL) + soil * 0.04
    iso = (
        AREA * 2.0 * soil / (np.pi * b_prime + d_t) * np.log(np.pi * b_prime / d_t + 1.0)
    )
    assert independent == pytest.approx(iso, rel=0.03)


def _check_the_committed_mesh_study(committed, flow, kiva_mesh_flow):
    """Assert that a BESTEST case's committed mesh study is ``bestest_gc30a.mesh_study``'s:
    the meshes, the test mesh's flow (recomputed here: ``flow`` [W]) and Kiva's default mesh's
    (``kiva_mesh_flow`` [W]), the Richardson limit and order; returns (first, growth) -> flow."""
    study = load_script(REF / "bestest_gc30a.py")
    meshes = [(m["first_cell_m"], m["growth"]) for m in committed["meshes"]]
    assert meshes == study.MESHES
    assert committed["test_mesh"]["floor_W"] == pytest.approx(flow, rel=1e-6)
    assert committed["kiva_default_mesh_W"] == pytest.approx(kiva_mesh_flow, rel=1e-6)
    by_mesh = {mesh: m["floor_W"] for mesh, m in zip(meshes, committed["meshes"], strict=True)}
    assert by_mesh[study.TEST_MESH] == committed["test_mesh"]["floor_W"]
    assert by_mesh[(0.02, 1.5)] == committed["kiva_default_mesh_W"]
    halved = [by_mesh[(f, 1.05)] for f in (0.0025, 0.00125, 0.000625)]
    converged, order = study.richardson(*halved)
    assert committed["converged_W"] == pytest.approx(converged, rel=1e-12)
    assert committed["observed_order"] == pytest.approx(order, rel=1e-12)
    return by_mesh


def test_the_independent_section_meets_bestest_gc30a():
    """The independent solution above on IEA BESTEST GC30a (NREL/TP-550-43388; 12 x 12 m floor
    at 30 C, grade at 10 C, soil 1.9 W/(m K), deep ground at 10 C 30 m down, far field 20 m;
    as Kiva's own unit test sets it up): its steady floor heat flow within the range of the
    three verified numerical models (TRNSYS 2,642, FLUENT 2,585, MATLAB 2,695 W, as transcribed
    in bigladder/kiva's ``foundation.unit.cpp``; sources in ``bestest_gc30a.py``) widened by
    2 %, on a mesh 0.17 % below the mesh-converged value (2,699.4 against 2,703.9 W; Kiva's
    default mesh gives 2,623.5). ``gc30a.json`` must be what ``bestest_gc30a.py`` writes.
    Measured 2026-11-30: about 3 s."""
    script = load_script(REF / "bestest_gc30a.py")
    committed = json.loads((REF / "gc30a.json").read_text())
    verified = [script.PUBLISHED[name] for name in script.VERIFIED]
    low, high = 0.98 * min(verified), 1.02 * max(verified)

    flow = script.gc30a_flow(*script.TEST_MESH)
    assert low <= flow <= high
    assert low <= committed["converged_W"] <= high
    assert flow == pytest.approx(committed["converged_W"], rel=0.005)

    # the committed values are the script's
    assert committed["case"] == script.CASE
    assert committed["published_W"] == script.PUBLISHED
    assert committed["verified_range_W"] == [min(verified), max(verified)]
    _check_the_committed_mesh_study(committed, flow, script.gc30a_flow(0.02, 1.5))


def test_the_independent_section_meets_bestest_gc10a():
    """The independent solution above on IEA BESTEST GC10a, the analytical case (NREL/TP-550-
    43388; GC30a's floor and soil with the wall's top held linear from 30 to 10 C and Kiva's
    default domain, the deep ground at 10 C 40 m down, the far field 40 m; as Kiva's own unit
    test sets it up; sources in ``bestest_gc10a.py``). The analytical 2,432.597 W (Delsante,
    Stokes & Walsh 1983, as transcribed in bigladder/kiva's ``foundation.unit.cpp``) is a
    three-dimensional floor in a half-space: the script evaluates it from that definition (to
    0.2 ppm) and the same boundary on the two-dimensional ``A / P`` section in closed form,
    2,460.93 W, so the section's approximation costs +1.165 %, exactly. On Kiva's 40 m domain
    the section gives 2,465.8 W mesh-converged (2,465.7 on the test mesh, -0.004 %), +1.37 %
    above the analytical value: asserted within 0 to +1.5 % of it, and within 0 to +0.3 % of
    the exact two-dimensional value (+0.19 %: Kiva's 40 m domain +0.22 %, the mesh's growth
    -0.02 %; at 1,000 m the section meets it within 0.007 %), so a change of 0.2 % either way
    in the soil's conductivity fails it. ``gc10a.json`` must be what ``bestest_gc10a.py``
    writes. Measured 2026-11-30: about 3.5 s."""
    script = load_script(REF / "bestest_gc10a.py")
    committed = json.loads((REF / "gc10a.json").read_text())
    analytical = script.PUBLISHED["analytical"]

    # the published value is the case's definition; the A / P section's cost
    assert script.rectangle_flow() == pytest.approx(analytical, rel=1e-6)
    strip = script.strip_flow()
    assert strip / analytical - 1.0 == pytest.approx(0.01165, abs=5e-5)

    flow = script.gc10a_flow(*script.TEST_MESH)
    for value in (flow, committed["converged_W"]):
        assert 0.0 < value / analytical - 1.0 < 0.015
        assert 0.0 < value / strip - 1.0 < 0.003
    assert flow == pytest.approx(committed["converged_W"], rel=0.0005)
    assert committed["domains"][-1]["floor_W"] == pytest.approx(strip, rel=2e-4)

    # the committed values are the script's
    assert committed["case"] == script.CASE
    assert committed["published_W"] == script.PUBLISHED
    evaluated = committed["analytical_evaluated_W"]
    assert evaluated["rectangle_mitred_corners"] == pytest.approx(script.rectangle_flow(), 1e-12)
    assert evaluated["strip_A_over_P_section"] == pytest.approx(strip, rel=1e-12)
    assert evaluated["rectangle_product_corners"] == pytest.approx(
        script.rectangle_flow(corners="product"), rel=1e-12
    )
    assert committed["a_over_p_section_cost"] == pytest.approx(strip / analytical - 1, 1e-12)
    assert script.MESHES == load_script(REF / "bestest_gc30a.py").MESHES
    by_mesh = _check_the_committed_mesh_study(committed, flow, script.gc10a_flow(0.02, 1.5))
    domains = [
        (d["far_field_and_deep_ground_m"], d["first_cell_m"], d["growth"])
        for d in committed["domains"]
    ]
    assert domains == script.DOMAINS
    assert committed["domains"][0]["floor_W"] == by_mesh[script.TEST_MESH]


def test_the_insulation_keeps_the_edge_through_the_wall():
    """Insulation under the slab leaves the slab's edge on the foundation wall (Kiva keeps
    21-23 W/K more than ISO 13370 there, ground_study.json): the wall adds 12.6 W/K to the
    insulated floor (39.8 against 27.2 W/K without a wall; measured 2026-11-30), and the
    insulated floor loses about 15 W/K more than ISO 13370's whole-floor insulation (23.4)."""
    from thermocal.physics.ground import iso13370_slab_on_ground

    ground = FoundationGround(PERIMETER, soil=KIVA_DEFAULT_SOIL, wall_layers=WALL)
    insulated = steady_floor_conductance(ground, AREA, INSULATED)
    no_wall = steady_floor_conductance(FoundationGround(PERIMETER), AREA, INSULATED)
    assert insulated - no_wall == pytest.approx(12.6, abs=1.5)
    r_floor = sum(t / k for t, k, *_ in INSULATED)
    iso = AREA * iso13370_slab_on_ground(
        AREA, PERIMETER, wall_thickness=0.2286, floor_resistance=r_floor, soil_conductivity=0.864
    )
    assert insulated - iso > 10.0


def test_grid_is_consistent():
    """Every cell's capacity is its volume's (times the perimeter), the links are symmetric
    pairs with positive conductances, and the soil's volume is the domain's."""
    ground = FoundationGround(PERIMETER, soil=KIVA_DEFAULT_SOIL, wall_layers=WALL)
    grid = foundation_grid(ground, AREA, FLOOR)
    n = len(grid.capacity)
    assert grid.edge_node == n - 1
    assert np.all(grid.links[:, 2] > 0) and np.all(grid.links[:, :2] < n)
    soil_rc = KIVA_DEFAULT_SOIL[1] * KIVA_DEFAULT_SOIL[2]
    width = AREA / PERIMETER + 0.2286 + 40.0
    # soil: the whole domain 40 m deep, less the wall above its bottom, plus the fill above the
    # grade under the slab (0.2 - 0.114 m)
    soil_volume = width * 40.0 + AREA / PERIMETER * (0.2 - 0.1143)
    wall_rc = sum(t * r * c for t, _, r, c in WALL) * 0.1143
    total = (soil_volume * soil_rc + wall_rc) * PERIMETER
    assert grid.capacity[:-1].sum() == pytest.approx(total, rel=0.01)
    assert grid.under_floor[:, 1].min() > 0 and len(grid.outdoor) > 0


def test_bad_foundation_input_is_refused():
    with pytest.raises(ThermocalInputError, match="exposed_perimeter"):
        FoundationGround(0.0)
    with pytest.raises(ThermocalInputError, match="soil conductivity"):
        FoundationGround(10.0, soil=(-1.0, 1500.0, 1000.0))
    with pytest.raises(ThermocalInputError, match="wall layer"):
        FoundationGround(10.0, wall_layers=((0.2, 1.0, 1000.0),))


def test_house_steady_heat_loss_against_energyplus(tmp_path):
    """The whole house on its ground sections, held at 20 C above a constant 0 C without sun
    or gains (the IDF EnergyPlus ran, its weather made steady as make_reference.py made it):
    286.5 W/K against EnergyPlus's 299.2 (-4.2 %; floors adiabatic 246.1 against 246.0, so the
    two floors' ground 40 against 53 W/K). The ground starts in its steady state
    (``Simulation._initial_state``), as Kiva's does; half a year lets the rest settle."""
    import warnings

    from conftest import shared_data_path
    from thermocal.io.weather import read_weather
    from thermocal.multizone import Simulation, load_building

    mr = load_script(REF / "make_reference.py", "make_reference_house")
    epw = shared_data_path("weather_switzerland", "Zuerich-SMA_2015.epw")
    weather, meta = read_weather(mr.steady_weather(Path(epw), tmp_path / "steady.epw"))
    idf = tmp_path / "house_without_gains.idf"
    idf.write_text(mr.house_idf(gains=False))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = load_building(idf)
    sim = Simulation(
        building, weather, meta, start="2015-01-01", end="2015-07-01", warmup_days=0,
        initial_temperature=20.0,
    )  # fmt: skip
    heating = sim.run().heating["LIVING ZONE"]
    hlc = float(heating.iloc[-len(heating) // 20 :].mean()) / 20.0
    reference = json.loads((REF / "reference.json").read_text())["heat_loss_coefficient_W_per_K"]
    assert hlc == pytest.approx(reference, rel=0.08)
    assert hlc == pytest.approx(286.5, rel=0.02)


def test_foundations_round_trip_through_a_building_file(tmp_path):
    """An imported house's ground sections survive ``save_building`` / ``load_building``
    (the calibrated file of a Kiva house keeps them), and a misspelt field is refused."""
    import warnings

    import yaml

    from thermocal.multizone import load_building
    from thermocal.multizone.files import building_from_dict, building_to_dict, save_building

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = load_building(REF / "house_v25.idf")
    path = save_building(building, tmp_path / "house.yaml")
    again = load_building(path)
    assert again.foundations == building.foundations
    data = yaml.safe_load(path.read_text())
    data["foundations"]["Living:Floor"]["perimeter"] = 40.0
    with pytest.raises(ThermocalInputError, match="'Living:Floor': expected the fields"):
        building_from_dict(data)
    data = building_to_dict(building)
    data["foundations"] = {"Living:North": {"exposed_perimeter": 10.0}}
    with pytest.raises(ThermocalInputError, match="must name surfaces with boundary: ground"):
        building_from_dict(data)


def test_the_reduced_section_follows_the_full_one():
    """Balanced truncation (``NetworkOptions.foundation_states``, default 16) against every cell:
    the same steady heat loss coefficient to rounding, and the house's heating over a Zurich
    winter month (the floors' ground started in its steady state) within 0.3 %."""
    import warnings

    from conftest import shared_data_path
    from thermocal.io.weather import read_weather
    from thermocal.multizone import Simulation, load_building
    from thermocal.multizone.network import NetworkOptions
    from thermocal.multizone.simulation import steady_state_heat_loss_coefficient

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = load_building(REF / "house_v25.idf")
    full, reduced = NetworkOptions(foundation_states=None), NetworkOptions()
    assert reduced.foundation_states == 16
    assert steady_state_heat_loss_coefficient(building, options=reduced) == pytest.approx(
        steady_state_heat_loss_coefficient(building, options=full), rel=1e-9
    )
    weather, meta = read_weather(shared_data_path("weather_switzerland", "Zuerich-SMA_2015.epw"))
    heating = []
    for options in (full, reduced):
        sim = Simulation(
            building, weather, meta, start="2015-01-01", end="2015-02-01", options=options
        )
        assert len(sim.network.foundation_nodes) == (656 if options is full else 32)
        heating.append(float(sim.run().heating["LIVING ZONE"].sum()))
    assert heating[1] == pytest.approx(heating[0], rel=0.003)


def test_a_basements_walls_above_the_grade_are_ground_faces(tmp_path):
    """A basement whose walls stand 0.3 m above the grade (the DOE prototype's basement, its
    ``Foundation:Kiva`` wall height above grade raised from 0): each wall's part above the grade
    is an exterior face of Kiva's boundary (its own per-step correction, the wall's sun, the sky
    share 0.354) besides the grade; the reduced section follows every cell's within 0.5 % of a
    winter month's heating, and reruns are bit-identical (a face's first step reads no earlier
    run's correction)."""
    import warnings

    from conftest import shared_data_path
    from thermocal.io.weather import read_weather
    from thermocal.multizone import Simulation, load_building
    from thermocal.multizone.network import NetworkOptions

    source = (REF.parent / "retrofit_energyplus_basement" / "house_v25.idf").read_text()
    line = "Foundation:Kiva, Basement Foundation, 15, , , , , , , , , , , 0.0;"
    assert line in source
    path = tmp_path / "basement_above_grade.idf"
    path.write_text(source.replace(line, line.replace("0.0;", "0.3;")))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = load_building(path)
    weather, meta = read_weather(shared_data_path("weather_switzerland", "Zuerich-SMA_2015.epw"))
    heating = []
    for options in (NetworkOptions(foundation_states=None), NetworkOptions()):
        sim = Simulation(
            building, weather, meta, start="2015-01-01", end="2015-01-15", options=options
        )
        names = list(sim.network.ground_faces.names)
        # the grade and the four walls of the floor's section
        assert names[0] == "Extfloor_unit1/grade" and len(names) == 5, names
        assert all(n.startswith("Extfloor_unit1/wall/") for n in names[1:]), names
        first = sim.run().heating.sum().sum()
        assert sim.run().heating.sum().sum() == first
        heating.append(float(first))
    assert heating[1] == pytest.approx(heating[0], rel=0.005)
