"""Citations used in the user-facing text of the retrofit workflow (report, CLI, docs).

One place, so every output names the method the same way. User-facing text speaks of "the
fifth-order RC method" and cites it once, in the report's references section.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Reference:
    key: str  # short in-text form, e.g. "Madsen et al. (2016)"
    text: str  # full entry of the references list
    doi: str | None = None

    def entry(self) -> str:
        """The full entry, with the DOI when known (plain text, no link: reports stay offline)."""
        return f"{self.text} doi:{self.doi}" if self.doi else self.text


#: The retrofit method itself. Its authors, venue and DOI are not part of the text thermocal
#: was built from; the case study (St. Gallen, Switzerland; measurements February - March 2019)
#: identifies it. Complete this entry when the bibliographic data are at hand.
RETROFIT_METHOD = Reference(
    key="the fifth-order RC method",
    text=(
        '"A Calibrated RC Model for Data-Driven Retrofit Analysis of a Residential Building": '
        "fifth-order grey-box RC model calibrated by maximum likelihood on three weeks of hourly "
        "measurements, validated on the next three weeks, annual heating demand and 16 envelope-"
        "retrofit strategies (case study: single-family house of 1953 in the canton of St. "
        "Gallen, Switzerland, measured February - March 2019)."
    ),
)

MADSEN_2016 = Reference(
    key="Madsen et al. (2016)",
    text=(
        "Madsen, H., Bacher, P., Bauwens, G., Deconinck, A.-H., Reynders, G., Roels, S., "
        "Himpe, E., Lethe, G. (2016). Thermal performance characterization using time series "
        "data - IEA EBC Annex 58 guidelines. KU Leuven / IEA EBC."
    ),
)

BACHER_MADSEN_2011 = Reference(
    key="Bacher and Madsen (2011)",
    text=(
        "Bacher, P., Madsen, H. (2011). Identifying suitable models for the heat dynamics of "
        "buildings. Energy and Buildings 43(7), 1511-1522."
    ),
    doi="10.1016/j.enbuild.2011.02.005",
)

SIGRIST_2019 = Reference(
    key="Sigrist et al. (2019)",
    text=(
        "Sigrist et al. (2019), cited by the fifth-order RC method for the four most frequent "
        "envelope measures in Switzerland and their cost-optimal variants (its Table 1)."
    ),
)

GEG_2020 = Reference(
    key="GEG (2020), Anlage 9",
    text=(
        "Gebaeudeenergiegesetz (GEG), Germany, 2020, Anlage 9: greenhouse-gas emission factors "
        "of energy carriers in g CO2-equivalent per kWh of final energy (heating oil 310, "
        "natural gas 240, liquid gas 270, grid electricity 560, wood 20)."
    ),
)

ISO_STANDARDS = Reference(
    key="ISO 52016-1, ISO 52010-1, ISO 13370, ISO 6946, ISO 13789",
    text=(
        "ISO 52016-1:2017 (surface coefficients, areal heat capacities), ISO 52010-1:2017 (solar "
        "irradiance on surfaces), ISO 13370:2017 (heat transfer via the ground), ISO 6946:2017 "
        "(surface resistances, U-values), ISO 13789:2017 (ventilation heat transfer)."
    ),
)

ALL = (RETROFIT_METHOD, MADSEN_2016, BACHER_MADSEN_2011, SIGRIST_2019, GEG_2020, ISO_STANDARDS)
