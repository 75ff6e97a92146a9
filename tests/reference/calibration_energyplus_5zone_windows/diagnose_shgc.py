"""Why the calibrated SHGC of this twin ends at its upper limit: the glazing's SHGC ceiling and
the metric's slice.

Run from the repository root after ``make_reference.py`` (about 15 s)::

    PYTHONPATH=src python tests/reference/calibration_energyplus_5zone_windows/diagnose_shgc.py

Two measurements, written to ``diagnose_shgc.json``:

- ``ceiling``: for the double glazing as thermocal reads it from the nominal and from the hidden
  file, the normal-incidence solar transmittance, the panes' absorptances and the largest SHGC
  the model realises. ``WindowType.with_shgc`` scales transmittance and absorptances by
  ``shgc / nominal shgc``, which cannot exceed ``1 / (T + sum A)`` (nothing reflected): a
  larger SHGC was simulated as the ceiling's until 2026-11-29 and is refused since
  (``WindowType.shgc_limit``), so the slice stops at the nominal glazing's ceiling.
- ``slice``: the campaign's zone-group metric [W^2] with every varied parameter at its truth
  but the SHGC (this twin), and the same on the first 5-zone twin (its own log and truth, clear
  double glazing): where along the SHGC the metric is smallest when everything else is right.
"""

from __future__ import annotations

import json
import tempfile
import warnings
from pathlib import Path

from calibrate_twin import (  # this folder's script (run as a script: its folder is on the path)
    HERE,
    INCLUDE,
    WINDOW_SHGC,
    WINDOW_U,
    base,
    folder_make_reference,
    prepare,
    truth_file,
)

mr = folder_make_reference()
GLAZING = "Dbl Clr 3mm/13mm Air"
SLICE = (0.60, 0.744, 0.7635, 0.80, 0.85, 0.875)


def ceiling(idf_text: str, folder: Path) -> dict:
    """Optics of :data:`GLAZING` as thermocal reads them from an IDF text (loads removed) and
    the largest SHGC the model realises [-]."""
    from thermocal.multizone.idf import read_idf

    path = Path(folder) / "read.idf"
    path.write_text(mr.base.twin_idf(mr.without_loads(idf_text), mr.DAYS))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        window = read_idf(path).window_types[GLAZING]
    total = window.solar_transmittance + sum(window.pane_absorptances)
    return {
        "shgc": float(window.shgc),
        "solar_transmittance": float(window.solar_transmittance),
        "pane_absorptances": [float(a) for a in window.pane_absorptances],
        "largest_realised_shgc": float(window.shgc / total),
    }


def metric_slice(campaign_path: Path, truth: dict, values=SLICE) -> dict:
    """The zone-group metric [W^2] at ``truth`` with the SHGC set to each of ``values``."""
    from thermocal.calibration.config import load_campaign

    campaign = load_campaign(campaign_path)
    out = {}
    for value in values:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            point = {**truth, WINDOW_SHGC: value}
            out[f"{value:.4g}"] = base.true_metric(campaign, point, "groups")
    return out


def run() -> dict:
    """Both measurements; writes ``diagnose_shgc.json``."""
    source = (mr.SHARED / mr.IDF_NAME).read_text()
    this = truth_file()
    first = json.loads((Path(base.__file__).parent / "truth.json").read_text())
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        out["ceiling"] = {
            "nominal": ceiling(source, tmp),
            "hidden": ceiling(mr.hidden(source), tmp),
        }
        (tmp / "a").mkdir()
        truth = {n: this["truth"][n] for n in INCLUDE}
        out["slice_this_twin"] = metric_slice(prepare(tmp / "a", 48), truth)
        (tmp / "b").mkdir()
        path = base.prepare(tmp / "b", 48)  # the first twin's log; its campaign plus the window
        path.write_text(
            path.read_text().replace("include: [", f'include: ["{WINDOW_SHGC}", "{WINDOW_U}", ')
        )
        varied = ("construction/WALL", "construction/ROOF", "zone/SPACE", f"window/{GLAZING}")
        truth = {n: v for n, v in first["truth"].items() if n.startswith(varied)}
        out["slice_first_twin"] = metric_slice(path, truth)
    (HERE / "diagnose_shgc.json").write_text(json.dumps(out, indent=2) + "\n")
    return out


if __name__ == "__main__":
    print(json.dumps(run(), indent=1))
