"""A small builder of self-contained HTML reports (one file, figures embedded as base64 PNG).

Example::

    report = HtmlReport("Retrofit analysis", subtitle="Demo house")
    report.heading("Calibration")
    report.key_values({"Heat loss coefficient": "484 +/- 12 W/K"})
    report.table(frame, caption="Parameters", number_format="{:,.3g}")
    report.figure(fig, caption="Measured vs simulated")
    report.write("out/report.html")
"""

from __future__ import annotations

import base64
import datetime as _dt
import html
from collections.abc import Callable, Mapping
from pathlib import Path

import pandas as pd

from thermocal.report.figures import close, figure_to_base64

_CSS = """
body{font-family:-apple-system,BlinkMacSystemFont,"Segoe UI",Roboto,Helvetica,Arial,sans-serif;
 margin:0;background:#f4f6f8;color:#1f2933;line-height:1.45}
header{background:linear-gradient(120deg,#12355b,#1b6ca8);color:#fff;padding:28px 48px}
header h1{margin:0 0 4px 0;font-weight:600}
header p{margin:0;opacity:.85}
main{max-width:1100px;margin:0 auto;padding:24px 32px 64px}
section{background:#fff;border-radius:10px;box-shadow:0 1px 3px rgba(0,0,0,.08);
 padding:18px 26px;margin:18px 0}
h2{color:#12355b;border-bottom:2px solid #e4e9ef;padding-bottom:6px;margin-top:4px}
h3{color:#1b6ca8;margin-bottom:6px}
table{border-collapse:collapse;width:100%;margin:8px 0 4px;font-size:14px}
caption{caption-side:top;text-align:left;font-weight:600;color:#52606d;padding:4px 0}
th{background:#12355b;color:#fff;font-weight:600;padding:7px 10px;text-align:left}
td{padding:6px 10px;border-bottom:1px solid #e4e9ef;font-variant-numeric:tabular-nums}
td.num,th.num{text-align:right}
tr:nth-child(even) td{background:#f8fafc}
tr:hover td{background:#eef5fb}
tr.highlight td{background:#fff4e5;font-weight:600}
.kv{display:grid;grid-template-columns:repeat(auto-fill,minmax(230px,1fr));gap:12px;margin:8px 0}
.kv div{background:#f8fafc;border-left:4px solid #1b6ca8;border-radius:6px;padding:8px 12px}
.kv .k{font-size:12px;color:#52606d;text-transform:uppercase;letter-spacing:.04em}
.kv .v{font-size:19px;font-weight:600;color:#12355b}
figure{margin:12px 0}
figure img{max-width:100%;border:1px solid #e4e9ef;border-radius:6px}
figcaption{font-size:13px;color:#52606d;margin-top:4px}
.note{background:#fff8e1;border-left:4px solid #f0b400;padding:8px 12px;border-radius:6px;
 font-size:14px}
.flag{background:#fdecea;border-left:4px solid #c0392b;padding:6px 12px;border-radius:6px;
 font-size:14px;margin:4px 0}
footer{color:#7b8794;font-size:12px;text-align:center;padding:16px}
p.lead{font-size:17px;line-height:1.5;color:#12355b}
p.small{font-size:12px;color:#52606d}
header img.logo{float:right;max-height:56px;max-width:220px;margin-left:16px}
ol.refs li,ul.bullets li{margin:3px 0;font-size:14px}
"""

#: Print stylesheet: A4 pages, no shadows or backgrounds that waste toner, tables and figures
#: kept on one page, repeated table headers, headings kept with what follows them.
PRINT_CSS = """
@page{size:A4;margin:14mm 12mm 16mm 12mm}
@media print{
 body{background:#fff;font-size:11pt;color:#000}
 header{background:#12355b !important;-webkit-print-color-adjust:exact;print-color-adjust:exact;
  padding:14px 18px}
 main{max-width:none;padding:0}
 section{box-shadow:none;border-radius:0;padding:6px 0;margin:10px 0;border-top:1px solid #ccc}
 section:first-of-type{border-top:none}
 h2,h3,caption{break-after:avoid;page-break-after:avoid}
 table,figure,.kv,.flag,.note{break-inside:avoid;page-break-inside:avoid}
 thead{display:table-header-group}
 tr,td,th{break-inside:avoid;page-break-inside:avoid}
 th{-webkit-print-color-adjust:exact;print-color-adjust:exact}
 tr:hover td{background:inherit}
 table{font-size:9pt}
 figure img{max-width:100%;border:none}
 footer{position:running(footer)}
 a{color:inherit;text-decoration:none}
}
"""


class HtmlReport:
    """Accumulates report blocks and writes one self-contained HTML file.

    Parameters
    ----------
    title : str
    subtitle : str, optional
    lang : str
        Language of the document (``<html lang>``).
    logo : bytes or path, optional
        PNG, JPEG or SVG shown in the header, embedded as a data URI (the file stays offline).
    css : str, optional
        Extra CSS appended to the built-in screen and print stylesheets.
    """

    def __init__(
        self,
        title: str,
        *,
        subtitle: str = "",
        lang: str = "en",
        logo: bytes | Path | str | None = None,
        css: str = "",
    ) -> None:
        self.title = title
        self.subtitle = subtitle
        self.lang = lang
        self.logo = logo
        self.css = css
        self._sections: list[list[str]] = [[]]

    # ------------------------------------------------------------------ blocks
    def section(self, title: str) -> HtmlReport:
        """Start a new card-like section with a level-2 heading."""
        self._sections.append([f"<h2>{html.escape(title)}</h2>"])
        return self

    def heading(self, text: str, level: int = 3) -> HtmlReport:
        self._current.append(f"<h{level}>{html.escape(text)}</h{level}>")
        return self

    def paragraph(self, text: str, *, css_class: str | None = None) -> HtmlReport:
        """A paragraph of plain text (escaped)."""
        cls = f' class="{css_class}"' if css_class else ""
        self._current.append(f"<p{cls}>{html.escape(text)}</p>")
        return self

    def note(self, text: str) -> HtmlReport:
        return self.paragraph(text, css_class="note")

    def flags(self, messages) -> HtmlReport:
        """Warnings, one box each."""
        for m in messages:
            self._current.append(f'<div class="flag">{html.escape(str(m))}</div>')
        return self

    def key_values(self, items: Mapping[str, str]) -> HtmlReport:
        """Prominent key figures as a grid of tiles."""
        tiles = "".join(
            f'<div><div class="k">{html.escape(str(k))}</div>'
            f'<div class="v">{html.escape(str(v))}</div></div>'
            for k, v in items.items()
        )
        self._current.append(f'<div class="kv">{tiles}</div>')
        return self

    def table(
        self,
        frame: pd.DataFrame,
        *,
        caption: str = "",
        index: bool = False,
        number_format: str | Mapping[str, str] | Callable = "{:,.4g}",
        highlight_rows=(),
    ) -> HtmlReport:
        """A DataFrame as a styled table; numbers right-aligned and formatted.

        Parameters
        ----------
        number_format : str, mapping column -> str, or callable
            Format of numeric cells.
        highlight_rows : iterable
            Row positions (0-based) to emphasise.
        """
        # an unnamed index heads its column with nothing, not pandas' "index"
        df = frame.rename_axis(frame.index.name or "").reset_index() if index else frame
        highlight = set(highlight_rows)
        head = "".join(
            f'<th class="{"num" if pd.api.types.is_numeric_dtype(df[c]) else ""}">'
            f"{html.escape(str(c))}</th>"
            for c in df.columns
        )
        rows = []
        for pos, (_, row) in enumerate(df.iterrows()):
            cells = []
            for c in df.columns:
                v = row[c]
                if isinstance(v, int | float) and not isinstance(v, bool):
                    fmt = (
                        number_format.get(c, "{:,.4g}")
                        if isinstance(number_format, Mapping)
                        else number_format
                    )
                    text = "" if pd.isna(v) else (fmt(v) if callable(fmt) else fmt.format(v))
                    if text.lstrip("-").strip("0.,") == "" and text.startswith("-"):
                        text = text[1:]  # "-0" or "-0.00": a value rounded to zero has no sign
                    cells.append(f'<td class="num">{html.escape(text)}</td>')
                else:
                    cells.append(f"<td>{html.escape('' if v is None else str(v))}</td>")
            cls = ' class="highlight"' if pos in highlight else ""
            rows.append(f"<tr{cls}>{''.join(cells)}</tr>")
        cap = f"<caption>{html.escape(caption)}</caption>" if caption else ""
        self._current.append(
            f"<table>{cap}<thead><tr>{head}</tr></thead><tbody>{''.join(rows)}</tbody></table>"
        )
        return self

    def figure(self, fig, *, caption: str = "", close_figure: bool = True) -> HtmlReport:
        """Embed a matplotlib figure (or PNG bytes already rendered) as base64 PNG."""
        if isinstance(fig, bytes | bytearray):
            data = base64.b64encode(bytes(fig)).decode("ascii")
        else:
            data = figure_to_base64(fig)
            if close_figure:
                close(fig)
        cap = f"<figcaption>{html.escape(caption)}</figcaption>" if caption else ""
        self._current.append(
            f'<figure><img alt="{html.escape(caption)}" src="data:image/png;base64,{data}"/>'
            f"{cap}</figure>"
        )
        return self

    def bullets(self, items, *, intro: str = "") -> HtmlReport:
        """A bulleted list of plain-text items, optionally after an introductory sentence."""
        if intro:
            self.paragraph(intro)
        lis = "".join(f"<li>{html.escape(str(i))}</li>" for i in items)
        self._current.append(f'<ul class="bullets">{lis}</ul>')
        return self

    def references(self, entries) -> HtmlReport:
        """A numbered list of references (plain text, no links: the report stays offline)."""
        lis = "".join(f"<li>{html.escape(str(e))}</li>" for e in entries)
        self._current.append(f'<ol class="refs">{lis}</ol>')
        return self

    def raw_html(self, fragment: str) -> HtmlReport:
        """Insert trusted HTML as is."""
        self._current.append(fragment)
        return self

    # ------------------------------------------------------------------ output
    @property
    def _current(self) -> list[str]:
        return self._sections[-1]

    def render(self) -> str:
        """The complete HTML document."""
        body = "".join(
            f"<section>{''.join(blocks)}</section>" for blocks in self._sections if blocks
        )
        stamp = _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC")
        from thermocal import __version__

        return (
            f'<!DOCTYPE html><html lang="{html.escape(self.lang)}"><head><meta charset="utf-8">'
            f'<meta name="viewport" content="width=device-width,initial-scale=1">'
            f"<title>{html.escape(self.title)}</title>"
            f"<style>{_CSS}{PRINT_CSS}{self.css}</style></head><body>"
            f"<header>{self._logo_html()}<h1>{html.escape(self.title)}</h1>"
            f"<p>{html.escape(self.subtitle)}</p>"
            f"</header><main>{body}</main><footer>thermocal {html.escape(__version__)} - "
            f"generated {stamp}</footer></body></html>"
        )

    def _logo_html(self) -> str:
        if self.logo is None:
            return ""
        data = self.logo
        mime = "image/png"
        if isinstance(data, str | Path):
            suffix = Path(data).suffix.lower()
            mime = {".svg": "image/svg+xml", ".jpg": "image/jpeg", ".jpeg": "image/jpeg"}.get(
                suffix, "image/png"
            )
            data = Path(data).read_bytes()
        elif data.lstrip()[:5] in (b"<?xml", b"<svg "):
            mime = "image/svg+xml"
        elif data[:3] == b"\xff\xd8\xff":
            mime = "image/jpeg"
        b64 = base64.b64encode(bytes(data)).decode("ascii")
        return f'<img class="logo" alt="logo" src="data:{mime};base64,{b64}"/>'

    def write(self, path: Path | str) -> Path:
        """Write the report to ``path`` (UTF-8) and return it."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(self.render(), encoding="utf-8")
        return path
