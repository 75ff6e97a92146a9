"""What ``thermocal simulate`` imports: none of the packages it does not need (issue 22 item 3).

Start-up is a large part of a short simulation (about 2.2 s of imports against EnergyPlus's
whole run; ``benchmarks/bench_startup.py`` lists each package's cost). The plotting,
meta-model, distributed and sampling libraries belong to the commands that use them; a module
that imports one of them at its top, on the simulate path, fails this test.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
NOT_FOR_SIMULATE = ("matplotlib", "sklearn", "dask", "distributed", "SALib", "emcee",
                    "statsmodels", "scipy.stats")  # fmt: skip

_SCRIPT = """
import atexit, sys
def _report():
    print("IMPORTED " + " ".join(sorted(m for m in sys.modules
                                        if m in {names!r} or m.split(".")[0] in {names!r})))
atexit.register(_report)
sys.argv = ["thermocal"] + {args!r}
from thermocal.cli import main
main()
"""


def test_simulate_imports_no_plotting_metamodel_or_distributed_package(tmp_path):
    import pvlib

    weather = Path(pvlib.__file__).parent / "data" / "723170TYA.CSV"
    building = ROOT / "examples" / "buildings" / "multizone_single_family_house.yaml"
    args = [
        "simulate", str(building), str(weather), "--start", "2001-01-10", "--end", "2001-01-11",
        "--step", "1h", "--warmup-days", "1", "--out", str(tmp_path / "out"),
    ]  # fmt: skip
    script = _SCRIPT.format(names=set(NOT_FOR_SIMULATE), args=args)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          timeout=300)  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]
    assert (tmp_path / "out" / "summary.json").is_file()
    line = [x for x in done.stdout.splitlines() if x.startswith("IMPORTED")][-1]
    assert line.split()[1:] == [], line
