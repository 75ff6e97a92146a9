"""Coverage summary of ``results.md`` (written by ``measure.py``): per twin, metric and
discrepancy scale, the 90 % intervals covering the truth, the parameters determined and the
median interval width over the truth. Run: python summarise.py (prints markdown)."""

from __future__ import annotations

import re
from collections import defaultdict
from pathlib import Path

HERE = Path(__file__).resolve().parent
MODES = ("none", "neighbours", "shared", "floor")


def rows():
    twin = None
    for line in (HERE / "results.md").read_text().splitlines():
        head = re.match(r"## (\w+)", line)
        if head:
            twin = head.group(1)
            continue
        cells = [c.strip() for c in line.strip("|").split("|")]
        if twin and len(cells) == 7 and "/" in cells[0] and cells[4] in ("True", "False"):
            metric, mode = cells[0].split("/")
            width = float(cells[5].rstrip(" %"))
            yield twin, metric, mode, cells[1], cells[4] == "True", width, cells[6] == "True"


def main() -> int:
    table = defaultdict(dict)
    for twin, metric, mode, name, covers, width, determined in rows():
        table[(twin, metric)].setdefault(mode, {})[name] = (covers, width, determined)
    print("| twin | metric | " + " | ".join(MODES) + " |")
    print("|---|---|" + "---|" * len(MODES))
    for (twin, metric), modes in table.items():
        cells = []
        for mode in MODES:
            r = modes.get(mode)
            if not r:
                cells.append("-")
                continue
            cov = sum(c for c, _, _ in r.values())
            det = sum(d for _, _, d in r.values())
            cells.append(f"{cov}/{len(r)} cover, {det} determined")
        print(f"| {twin} | {metric} | " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
