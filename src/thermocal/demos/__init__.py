"""Demonstration buildings and the generators of the shipped demo data.

The demos are built ON the library (the multi-zone model, the readers, the physics) and stand
apart from it: the library's packages reach them only from inside the functions that load a demo
(``thermocal demo``, ``thermocal identify --demo``, the calibrate workflow's demo inputs,
``thermocal verify --demo``), never at import time.

:mod:`thermocal.demos.buildings`
    Parametric test buildings generated from a rectangular floor plan (:func:`plan_building`,
    :class:`Room`, :class:`Storey`, :class:`Constructions`): the 1950s single-family house
    (``single_family_house()``, 9 zones, unheated cellar) and the single-storey clinic
    (``clinic()``, 180 rooms along three corridors, 186 zones). Formerly
    ``thermocal.multizone.generators``.
:mod:`thermocal.demos.retrofit`
    The retrofit demo's measurements: the house simulated by the multi-zone model with a
    radiator loop under thermostatic control, "measured" hourly like the retrofit method's
    wireless sensor network (``generate_demo_data``, ``write_demo_data``, ``prepare_demo``,
    ``audit_building``). Formerly ``thermocal.retrofit.demo_data``.
:mod:`thermocal.demos.verify`
    The post-retrofit verification demo: the same house with roof and walls retrofitted at a
    known date, so the avoided energy is known (``generate_verify_demo_data``,
    ``prepare_verify_demo``). Formerly in ``thermocal.retrofit.verify``, where its names still
    resolve.
:mod:`thermocal.demos.identification`
    The identification demo's sensor log: the clinic in January with perturbed envelope
    parameters, dual-duct HVAC and 82 event-reporting room sensors with offsets, dropouts and a
    dead sensor (``generate``, ``write_demo``, ``load_demo``). Formerly
    ``thermocal.identification.demo_data``.

The data the generators make ship in ``src/thermocal/data/`` and the tests regenerate them and
compare (``tests/retrofit/test_retrofit_demo.py``,
``tests/identification/test_identification_demo_data.py``,
``tests/retrofit/test_retrofit_verify.py``). Regenerate them with::

    python -m thermocal.demos.retrofit          # data/retrofit_demo
    python -m thermocal.demos.verify            # data/verify_demo (the house before/after)
    python -m thermocal.demos.identification --write src/thermocal/data/identification_demo

The old module paths (``thermocal.multizone.generators``, ``thermocal.retrofit.demo_data``,
``thermocal.identification.demo_data``) still import, with a :class:`DeprecationWarning`, and
hand on the same objects; the old ``python -m`` commands still run the generators.
"""
