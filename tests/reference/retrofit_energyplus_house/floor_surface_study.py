"""The living floor's steady heat loss in EnergyPlus 25.2 (Kiva), measured below its surface.

Run from the repository root (EnergyPlus 25.2; about 2 minutes)::

    PYTHONPATH=src python tests/reference/retrofit_energyplus_house/floor_surface_study.py \
        ../shared/data/weather_switzerland/Zuerich-SMA_2015.epw

The house of ``make_reference.py`` without internal gains, a year of the steady weather of its
heat loss coefficient (``steady_weather``: 0 C air, 3 m/s, no sun, the sky at the air
temperature; Kiva's ground settles at 0 C), the living zone held at 20 C; with the file's
carpet and without it (the floor's concrete alone). ``floor_surface.json``: the living floor's
inside-face conduction and inside-face temperature over the last week, and their ratio, the
conductance of the floor and its ground from the floor's surface to the outdoor air [W/K]: what
a ground model must give below the room's surface film, which a comparison from the room's air
mixes with the film (EnergyPlus's floor film, heat flowing down, is much weaker than ISO 6946's
0.17 m2 K/W).
"""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import make_reference as mr  # noqa: E402

OUTPUTS = (
    "Output:Variable, Living:Floor, Surface Inside Face Conduction Heat Transfer Rate, Hourly;\n"
    "Output:Variable, Living:Floor, Surface Inside Face Temperature, Hourly;\n"
)


def main(weather: str) -> dict:
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        steady = mr.steady_weather(Path(weather), tmp / "steady.epw")
        house = mr.house_idf(gains=False)
        cases = {
            "with_carpet": house,
            "without_carpet": house.replace(
                "Construction, FLOOR:LIVING, CC03, CP02;", "Construction, FLOOR:LIVING, CC03;"
            ),
        }
        for name, text in cases.items():
            assert "FLOOR:LIVING" in text
            frame = mr._run(text + OUTPUTS, steady, tmp / name)
            last = frame.iloc[-168:]
            loss = -float(mr._col(last, "Living:Floor:Surface Inside Face Conduction").mean())
            face = float(mr._col(last, "Living:Floor:Surface Inside Face Temperature").mean())
            out[name] = {
                "floor_loss_W": loss,
                "floor_face_C": face,
                "outdoor_C": 0.0,
                "below_surface_W_per_K": loss / face,
            }
    (HERE / "floor_surface.json").write_text(json.dumps(out, indent=1) + "\n")
    return out


if __name__ == "__main__":
    print(json.dumps(main(sys.argv[1]), indent=1))
