"""The report as a PDF through matplotlib's PDF backend (``PdfPages``): A4 pages, flowed top to bottom.

A small layout engine places headings, paragraphs, tables (split across pages with their header
repeated), the axis diagram and the plots on A4 figures, then adds the running footer with
"page n of N". Fonts are embedded as TrueType (``pdf.fonttype`` 42), so the text can be searched
and extracted. The content is the same ``ReportModel`` the HTML draws.
"""

from __future__ import annotations

import datetime as _dt
import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from drivetrain.report.blocks import KeyFigure, Table, Verdict
from drivetrain.report.diagram import aspect as diagram_aspect
from drivetrain.report.diagram import draw_matplotlib as draw_diagram
from drivetrain.report.display import fit_text, wrap_text
from drivetrain.report.formulas import markup_mathtext, markup_plain
from drivetrain.report.model import ReportModel
from drivetrain.report.plots import PlotSpec, draw_matplotlib, figure_ratio, mpl_text

if TYPE_CHECKING:
    from matplotlib.figure import Figure

PAGE_W, PAGE_H = 8.27, 11.69  # A4 [in]
MARGIN_L, MARGIN_R, MARGIN_T, MARGIN_B = 0.62, 0.62, 0.55, 0.75
CONTENT_W = PAGE_W - MARGIN_L - MARGIN_R
HEADING_H = 0.52
"""Height a section heading takes [in]: kept on one page with its section's first block."""

INK = "#1d2733"
MUTED = "#5b6673"
ACCENT = "#1f4e79"
LINE = "#d9dee4"
STATUS = {"pass": ("#1e7b34", "#e7f4ea"), "unknowns": ("#8a5a00", "#fbf3e0"), "fail": ("#b3261e", "#fcebea"),
          "info": ("#1f4e79", "#e9f0f8")}
_BOLD = ("pass", "fail", "strong")
CELL_COLORS = {"pass": "#1e7b34", "fail": "#b3261e", "muted": MUTED, "warn": "#8a5a00", "strong": INK}


def _wrap(text: str, width_in: float, size: float, bold: bool = False) -> list[str]:
    return wrap_text(text, width_in * 72.0, size, bold)


@dataclass
class _Cursor:
    fig: Figure
    y: float  # inches from the top of the page


class _Doc:
    """Flowed A4 pages of matplotlib figures."""

    def __init__(self, running_head: str) -> None:
        self.pages: list[Figure] = []
        self.head = running_head
        self.cur: _Cursor | None = None
        self.pending: tuple[str, float] | None = None  # a heading waiting for its first block

    # -- pages and primitives
    def new_page(self) -> _Cursor:
        from matplotlib.figure import Figure

        fig = Figure(figsize=(PAGE_W, PAGE_H))
        self.pages.append(fig)
        self.cur = _Cursor(fig, MARGIN_T)
        if len(self.pages) > 1:
            self.text(MARGIN_L, MARGIN_T - 0.12, self.head, size=7.5, color=MUTED)
            self.hline(MARGIN_T - 0.06, color=LINE)
            self.cur.y = MARGIN_T + 0.1
        return self.cur

    @property
    def c(self) -> _Cursor:
        return self.cur if self.cur is not None else self.new_page()

    def room(self) -> float:
        return PAGE_H - MARGIN_B - self.c.y

    def need(self, height: float) -> None:
        """Room for a block ``height`` tall, on a new page if this one has too little.

        A heading waiting for its first block (see ``heading``) goes down with it: on this page
        if both fit, else both on the next, so a heading never ends a page.
        """
        if self.pending is not None:
            text, keep = self.pending
            self.pending = None
            if self.cur is None or HEADING_H + max(height, keep) > self.room():
                self.new_page()
            self._draw_heading(text)
        if self.cur is None or height > self.room():
            self.new_page()

    def fx(self, x: float) -> float:
        return x / PAGE_W

    def fy(self, y: float) -> float:
        return 1.0 - y / PAGE_H

    def text(self, x: float, y: float, s: str, size: float = 8.5, color: str = INK, weight: str = "normal",
             ha: str = "left", va: str = "baseline", style: str = "normal", raw: bool = False) -> None:
        self.c.fig.text(self.fx(x), self.fy(y), s if raw else mpl_text(s), fontsize=size, color=color,
                        fontweight=weight, ha=ha, va=va, fontstyle=style)

    def rect(self, x: float, y: float, w: float, h: float, fc: str, ec: str = "none", lw: float = 0.0,
             rounded: bool = False) -> None:
        from matplotlib.patches import FancyBboxPatch, Rectangle

        fig = self.c.fig
        xy = (self.fx(x), self.fy(y + h))
        wf, hf = w / PAGE_W, h / PAGE_H
        patch: Any
        if rounded:
            patch = FancyBboxPatch(xy, wf, hf, boxstyle="round,pad=0,rounding_size=0.006", fc=fc, ec=ec, lw=lw,
                                   transform=fig.transFigure, mutation_aspect=PAGE_W / PAGE_H)
        else:
            patch = Rectangle(xy, wf, hf, fc=fc, ec=ec, lw=lw, transform=fig.transFigure)
        fig.add_artist(patch)

    def hline(self, y: float, color: str = LINE, lw: float = 0.6, x0: float = MARGIN_L,
              x1: float = PAGE_W - MARGIN_R) -> None:
        from matplotlib.lines import Line2D

        fig = self.c.fig
        fig.add_artist(Line2D([self.fx(x0), self.fx(x1)], [self.fy(y), self.fy(y)], color=color, lw=lw,
                              transform=fig.transFigure))

    # -- blocks
    def title_block(self, model: ReportModel) -> None:
        self.new_page()
        self.text(MARGIN_L, MARGIN_T + 0.12, f"DRIVETRAIN · {model.title.upper()}", size=8, color=MUTED)
        left_w = CONTENT_W - 3.55  # the meta block takes the right-hand 3.55 in
        name, size = fit_text(model.axis_name, 21.0, left_w * 72.0, bold=True, smallest=0.55)
        self.text(MARGIN_L, MARGIN_T + 0.5, name, size=size, weight="bold")
        y = MARGIN_T + 0.78
        for line in _wrap(model.subtitle, left_w, 9.5):
            self.text(MARGIN_L, y, line, size=9.5, color=MUTED)
            y += 0.17
        my = MARGIN_T + 0.2
        for k, v in model.meta:
            self.text(PAGE_W - MARGIN_R - 2.25, my, k, size=7.8, color=MUTED, ha="right")
            self.text(PAGE_W - MARGIN_R - 2.17, my, v, size=7.8, weight="bold")
            my += 0.16
        y = max(y, my) + 0.06
        self.hline(y, ACCENT, lw=2.0)
        self.c.y = y + 0.2

    def heading(self, text: str, keep: float = 1.6) -> None:
        """A section heading, drawn with the section's first block (at least ``keep`` inches of it)."""
        self.flush()
        self.pending = (text, keep)

    def flush(self) -> None:
        """Draw a heading still waiting for a block (a section that drew nothing)."""
        if self.pending is not None:
            self.need(0.0)

    def _draw_heading(self, text: str) -> None:
        y = self.c.y + 0.28
        self.text(MARGIN_L, y, text, size=13, color=ACCENT, weight="bold")
        self.hline(y + 0.08, ACCENT, lw=1.2)
        self.c.y = y + HEADING_H - 0.28

    def paragraph(self, text: str, size: float = 8.5, color: str = INK, style: str = "normal",
                  gap: float = 0.08) -> None:
        lh = size * 1.38 / 72.0
        for line in _wrap(text, CONTENT_W, size):
            self.need(lh)
            self.c.y += lh
            self.text(MARGIN_L, self.c.y - lh * 0.25, line, size=size, color=color, style=style)
        self.c.y += gap

    def verdict(self, v: Verdict) -> None:
        color, bg = STATUS[v.status]
        detail_lines = [line for d in v.details for line in _wrap("• " + d, CONTENT_W - 1.35, 8.5)]
        h = 0.5 + 0.155 * len(detail_lines)
        self.need(h + 0.1)
        y = self.c.y
        self.rect(MARGIN_L, y, CONTENT_W, h, bg, rounded=True)
        self.rect(MARGIN_L, y, 0.09, h, color)
        self.rect(MARGIN_L + 0.22, y + 0.14, 0.78, 0.3, color, rounded=True)
        if v.status == "unknowns":  # "PASS WITH UNKNOWNS" on two lines, to fit the badge
            for dy, word in ((0.215, "PASS WITH"), (0.365, "UNKNOWNS")):
                self.text(MARGIN_L + 0.61, y + dy, word, size=7, color="white", weight="bold", ha="center",
                          va="center")
        else:
            badge = {"pass": "PASS", "fail": "FAIL", "info": "INFO"}[v.status]
            self.text(MARGIN_L + 0.61, y + 0.29, badge, size=11, color="white", weight="bold", ha="center",
                      va="center")
        head = _wrap(v.headline, CONTENT_W - 1.35, 11.5)[0]
        self.text(MARGIN_L + 1.18, y + 0.34, head, size=11.5, weight="bold")
        ly = y + 0.54
        for line in detail_lines:
            self.text(MARGIN_L + 1.18, ly, line, size=8.5)
            ly += 0.155
        self.c.y = y + h + 0.16

    def key_figures(self, figs: list[KeyFigure]) -> None:
        per_row = 4
        gap = 0.1
        w = (CONTENT_W - gap * (per_row - 1)) / per_row
        h = 0.62
        for start in range(0, len(figs), per_row):
            self.need(h + gap)
            y = self.c.y
            for i, k in enumerate(figs[start:start + per_row]):
                x = MARGIN_L + i * (w + gap)
                self.rect(x, y, w, h, "#f4f6f9", ec=LINE, lw=0.6, rounded=True)
                self.text(x + 0.1, y + 0.17, k.label, size=7.5, color=MUTED)
                self.text(x + 0.1, y + 0.4, k.value, size=12.5, weight="bold")
                self.text(x + 0.1, y + 0.54, k.note, size=6.8, color=MUTED)
            self.c.y = y + h + gap
        self.c.y += 0.06

    def table(self, t: Table, size: float = 7.6) -> None:
        ncol = len(t.columns)
        weights = t.widths if t.widths and len(t.widths) == ncol else [1.0] * ncol
        total = sum(weights)
        widths = [CONTENT_W * wt / total for wt in weights]
        align = t.align.ljust(ncol, "l")
        pad = 0.06
        lh = size * 1.3 / 72.0
        has_head = any(t.columns)

        def wrapped(texts: list[str], bold: bool = False) -> list[list[str]]:
            return [_wrap(text, widths[i] - 2 * pad, size, bold) for i, text in enumerate(texts)]

        head_lines = wrapped(list(t.columns), True) if has_head else []
        head_h = (max(len(x) for x in head_lines) * lh + 2 * pad) if has_head else 0.0

        def draw_head(title: str) -> None:
            self.text(MARGIN_L, self.c.y + 0.16, title, size=9.5, weight="bold")
            self.c.y += 0.24
            if not has_head:
                return
            y = self.c.y
            self.rect(MARGIN_L, y, CONTENT_W, head_h, "#e9eef4")
            self.hline(y + head_h, "#b9c4d0", lw=1.0)
            x = MARGIN_L
            for i, lines in enumerate(head_lines):
                for j, line in enumerate(lines):
                    tx = x + pad if align[i] == "l" else x + widths[i] - pad
                    self.text(tx, y + pad + lh * (j + 0.78), line, size=size, weight="bold",
                              ha="left" if align[i] == "l" else "right")
                x += widths[i]
            self.c.y = y + head_h

        rows = [([_wrap(c.text, widths[i] - 2 * pad, size, c.cls in _BOLD) for i, c in enumerate(r)], r)
                for r in t.rows]
        heights = [max(len(x) for x in lines) * lh + 2 * pad for lines, _ in rows]
        whole = 0.24 + head_h + sum(heights) + 0.1
        page = PAGE_H - MARGIN_T - MARGIN_B - 0.1
        # A table that fits on one page starts on a fresh page rather than split; a long one splits
        # after at least three rows.
        self.need(whole if whole <= page * 0.7 else 0.24 + head_h + sum(heights[:3]) + 0.05)
        draw_head(t.title)
        for k, ((lines, cells), h) in enumerate(zip(rows, heights, strict=True)):
            if h > self.room():
                self.new_page()
                draw_head(t.title + " (continued)")
            y = self.c.y
            if k % 2 == 1:
                self.rect(MARGIN_L, y, CONTENT_W, h, "#f8f9fb")
            x = MARGIN_L
            for i, cell_lines in enumerate(lines):
                cls = cells[i].cls if i < len(cells) else ""
                color = CELL_COLORS.get(cls, INK)
                weight = "bold" if cls in _BOLD else "normal"
                for j, line in enumerate(cell_lines):
                    tx = x + pad if align[i] == "l" else x + widths[i] - pad
                    self.text(tx, y + pad + lh * (j + 0.78), line, size=size, color=color, weight=weight,
                              ha="left" if align[i] == "l" else "right")
                x += widths[i]
            self.hline(y + h, LINE, lw=0.5)
            self.c.y = y + h
        self.c.y += 0.06
        if t.note:
            self.paragraph(t.note, size=7, color=MUTED)
        self.c.y += 0.1

    def plot(self, spec: PlotSpec, max_h: float = 5.2) -> None:
        h = min(max_h, CONTENT_W * figure_ratio(spec) * 0.92)
        cap = _wrap(spec.caption, CONTENT_W, 7.2)
        self.need(h + 0.16 * len(cap) + 0.1)
        y = self.c.y
        rect = (self.fx(MARGIN_L + 0.55), self.fy(y + h), (CONTENT_W - 0.6) / PAGE_W, h / PAGE_H)
        draw_matplotlib(spec, self.c.fig, rect, fontsize=7.2)
        self.c.y = y + h + 0.04
        self.paragraph(spec.caption, size=7.2, color=MUTED)

    def diagram(self, model: ReportModel) -> None:
        h = CONTENT_W * diagram_aspect(model.diagram)
        cap = _wrap(model.diagram.caption, CONTENT_W, 7.2)
        self.need(h + 0.16 * len(cap) + 0.1)
        y = self.c.y
        draw_diagram(model.diagram, self.c.fig, (self.fx(MARGIN_L), self.fy(y + h), CONTENT_W / PAGE_W, h / PAGE_H))
        self.c.y = y + h + 0.06
        self.paragraph(model.diagram.caption, size=7.2, color=MUTED)

    def formulas(self, model: ReportModel) -> None:
        for f in model.formulas:
            sym = _wrap(markup_plain(f.symbols), CONTENT_W - 0.2, 7.2)
            src = _wrap(f"Source: {f.source} · {f.ref}", CONTENT_W - 0.2, 7.2)
            h = 0.22 + 0.2 * len(f.equations) + 0.04 + 0.13 * (len(sym) + len(src)) + 0.12
            self.need(h)
            y = self.c.y
            self.rect(MARGIN_L, y, CONTENT_W, h - 0.06, "white", ec=LINE, lw=0.6, rounded=True)
            self.text(MARGIN_L + 0.12, y + 0.2, f.title, size=8.6, weight="bold")
            ly = y + 0.2
            for q in f.equations:
                ly += 0.2
                self.text(MARGIN_L + 0.2, ly, markup_mathtext(q), size=9.2, raw=True)
            ly += 0.04
            for line in sym:
                ly += 0.13
                self.text(MARGIN_L + 0.12, ly, line, size=7.2, color=MUTED)
            for line in src:
                ly += 0.13
                self.text(MARGIN_L + 0.12, ly, line, size=7.2, color=INK)
            self.c.y = y + h

    def finish(self, path: Path, model: ReportModel) -> None:
        import matplotlib
        from matplotlib.backends.backend_pdf import PdfPages

        self.flush()
        n = len(self.pages)
        for k, fig in enumerate(self.pages, start=1):
            self.cur = _Cursor(fig, 0.0)
            y = PAGE_H - MARGIN_B + 0.3
            self.hline(y - 0.14, LINE)
            self.text(MARGIN_L, y, f"{model.axis_name} · {model.title}", size=7, color=MUTED)
            self.text(PAGE_W / 2, y, model.footer, size=7, color=MUTED, ha="center")
            self.text(PAGE_W - MARGIN_R, y, f"page {k} of {n}", size=7, color=MUTED, ha="right")
        meta: dict[str, Any] = {"Title": f"{model.axis_name} · {model.title}", "Subject": model.subtitle,
                                "Creator": model.footer.split(" · ")[0], "Keywords": "servo sizing, drivetrain"}
        epoch = os.environ.get("SOURCE_DATE_EPOCH")
        if epoch and epoch.strip().isdigit():
            meta["CreationDate"] = _dt.datetime.fromtimestamp(int(epoch), tz=_dt.UTC)
        with matplotlib.rc_context({"pdf.fonttype": 42, "font.family": "DejaVu Sans"}), \
                PdfPages(path, metadata=meta) as pdf:
            for fig in self.pages:
                pdf.savefig(fig)


def write_pdf(model: ReportModel, path: Path) -> None:
    """Lay the report out on A4 pages and save them to ``path`` (which the caller makes atomic)."""
    import matplotlib

    with matplotlib.rc_context({"pdf.fonttype": 42, "font.family": "DejaVu Sans", "mathtext.fontset": "dejavusans",
                                "axes.titlesize": 8, "axes.labelcolor": INK, "text.color": INK}):
        doc = _Doc(f"{model.axis_name} · {model.title}")
        doc.title_block(model)
        doc.verdict(model.verdict)
        doc.key_figures(model.key_figures)
        if model.checks is not None:
            doc.table(model.checks)
        def axis() -> None:
            doc.diagram(model)
            doc.table(model.inertia)

        def motion() -> None:
            doc.plot(model.motion, 5.0)
            doc.table(model.steps)

        def shaft() -> None:
            doc.plot(model.motor_shaft, 4.2)
            doc.table(model.demand)
            doc.table(model.segments)

        def plane() -> None:
            doc.plot(model.speed_torque, 4.3)
            if model.motor_data is not None:
                doc.table(model.motor_data)

        def mechanism() -> None:
            if model.mechanism_checks is not None:
                doc.table(model.mechanism_checks)
            if model.modes_plot is not None:
                doc.plot(model.modes_plot, 3.6)
            if model.modes is not None:
                doc.table(model.modes)

        def selection() -> None:
            for t in (model.candidates, model.ratios):
                if t is not None:
                    doc.table(t)

        sections: list[tuple[str, Callable[[], None]]] = [
            ("The axis", axis), ("Motion profile", motion), ("Motor shaft: speed and torque", shaft),
            ("Speed-torque plane", plane)]
        def electrical() -> None:
            if model.regen is not None:
                doc.plot(model.regen, 4.2)
            if model.electrical is not None:
                doc.table(model.electrical)

        if model.regen is not None or model.electrical is not None:
            sections.append(("Drive and regeneration", electrical))
        if model.mechanism_checks is not None or model.modes is not None:
            sections.append(("Mechanism: checks and modes", mechanism))

        def dynamics() -> None:
            for t in model.dynamics:
                doc.table(t)

        if model.dynamics:
            sections.append(("How it moves: the dynamic checks", dynamics))
        if model.candidates is not None or model.ratios is not None:
            sections.append(("Selection and ratio", selection))
        def order() -> None:
            for t in model.order:
                doc.table(t)

        if model.order:
            sections.append(("Order sheet", order))
        sections.append(("Inputs", lambda: doc.table(model.inputs)))
        sections.append(("Formulas and sources", lambda: doc.formulas(model)))
        for k, (title, draw) in enumerate(sections, start=1):
            doc.heading(f"{k} {title}")
            draw()
        doc.heading("Notes", keep=0.6)
        for note in model.notes:
            doc.paragraph(note, size=7.6, color=MUTED)
        doc.finish(path, model)
