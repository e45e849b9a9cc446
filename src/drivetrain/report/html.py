"""The report as one self-contained HTML file (plotly.js embedded), and as a notebook fragment.

Every string that comes from the user (axis name, motor name, keys and values of the axis file)
passes through ``html.escape``; plot labels are escaped for plotly's label markup, and the
figure JSON escapes ``<`` and ``>``, so nothing in an axis file can open a tag or a script.
"""

from __future__ import annotations

import html
import json
import re
from collections.abc import Callable
from importlib import resources
from string import Template
from typing import TYPE_CHECKING

from drivetrain.report.blocks import KeyFigure, Table, Verdict
from drivetrain.report.diagram import to_svg
from drivetrain.report.formulas import Formula, markup_html
from drivetrain.report.model import ReportModel, build_report
from drivetrain.report.plots import PlotSpec

if TYPE_CHECKING:
    from drivetrain.sizing.result import SizingResult

e = html.escape

PLOTLY_CONFIG = {"displaylogo": False, "responsive": True,
                 "modeBarButtonsToRemove": ["select2d", "lasso2d"],
                 "toImageButtonOptions": {"format": "png", "scale": 2}}


def _resource(name: str) -> str:
    return resources.files("drivetrain.report").joinpath(name).read_text(encoding="utf-8")


def _table(t: Table, extra_class: str = "") -> str:
    align = t.align.ljust(len(t.columns), "l")
    head = "".join(f'<th class="{align[i]}" scope="col">{e(c)}</th>' for i, c in enumerate(t.columns))
    rows = []
    for row in t.rows:
        cells = "".join(f'<td class="{align[i] if i < len(align) else "l"}{" " + c.cls if c.cls else ""}">'
                        f"{e(c.text)}</td>" for i, c in enumerate(row))
        rows.append(f"<tr>{cells}</tr>")
    thead = f"<thead><tr>{head}</tr></thead>" if any(t.columns) else ""
    note = f'<p class="dt-note">{e(t.note)}</p>' if t.note else ""
    cls = f"dt-table dt-{t.key}" + (f" {extra_class}" if extra_class else "")
    return (f'<div class="dt-table-wrap"><table class="{cls}" id="dt-table-{e(t.key)}"><caption>{e(t.title)}'
            f"</caption>{thead}<tbody>{''.join(rows)}</tbody></table></div>{note}")


BADGES = {"pass": "PASS", "unknowns": "PASS WITH UNKNOWNS", "fail": "FAIL", "info": "INFO"}
"""The verdict's badge for each status of a report's Verdict (the three outcomes of SizingResult.status)."""


def _verdict(v: Verdict) -> str:
    badge = BADGES[v.status]
    details = "".join(f"<li>{e(d)}</li>" for d in v.details)
    return (f'<section class="dt-verdict dt-{v.status}" id="dt-verdict"><div class="dt-badge">{badge}</div>'
            f"<div><h2>{e(v.headline)}</h2>{f'<ul>{details}</ul>' if details else ''}</div></section>")


def _kpis(figs: list[KeyFigure]) -> str:
    cards = "".join(f'<div class="dt-kpi"><div class="dt-kpi-label">{e(k.label)}</div>'
                    f'<div class="dt-kpi-value">{e(k.value)}</div><div class="dt-kpi-note">{e(k.note)}</div></div>'
                    for k in figs)
    return f'<section class="dt-kpis" aria-label="key figures">{cards}</section>'


def _formula(f: Formula) -> str:
    eqs = "".join(f'<div class="dt-eq">{markup_html(q)}</div>' for q in f.equations)
    return (f"<li><h4>{e(f.title)}</h4>{eqs}<p class=\"dt-sym\">{markup_html(f.symbols)}</p>"
            f'<p class="dt-src"><b>Source:</b> {e(f.source)} · <code>{e(f.ref)}</code></p></li>')


def _figure(spec: PlotSpec, plot: str) -> str:
    return (f'<figure class="dt-figure" id="dt-fig-{e(spec.key)}">{plot}'
            f"<figcaption>{e(spec.caption)}</figcaption></figure>")


def _mechanism_section(model: ReportModel, plot: Callable[[PlotSpec], str]) -> str:
    """The mechanism's checks table, and f1 across the stroke with the servo-bandwidth check ("" if none)."""
    out = _table(model.mechanism_checks) if model.mechanism_checks is not None else ""
    if model.modes_plot is not None:
        out += _figure(model.modes_plot, plot(model.modes_plot))
    if model.modes is not None:
        out += _table(model.modes)
    return out


def render_body(model: ReportModel, plot: Callable[[PlotSpec], str]) -> str:
    """The report's ``<div class="dt-report">``; ``plot`` renders one plot spec to HTML."""
    sections: list[tuple[str, str, str]] = []
    inertia = _table(model.inertia)
    diagram = (f'<figure class="dt-figure"><div class="dt-diagram-wrap">{to_svg(model.diagram)}</div>'
               f"<figcaption>{e(model.diagram.caption)}</figcaption></figure>")
    sections.append(("axis", "The axis", diagram + inertia))
    sections.append(("motion", "Motion profile", _figure(model.motion, plot(model.motion)) + _table(model.steps)))
    sections.append(("shaft", "Motor shaft: speed and torque",
                     _figure(model.motor_shaft, plot(model.motor_shaft)) + _table(model.demand)
                     + _table(model.segments)))
    motor = _figure(model.speed_torque, plot(model.speed_torque))
    if model.motor_data is not None:
        motor += _table(model.motor_data)
    sections.append(("motor", "Speed-torque plane", motor))
    mechanism = _mechanism_section(model, plot)
    if mechanism:
        sections.append(("mechanism", "Mechanism: checks and modes", mechanism))
    if model.dynamics:
        sections.append(("dynamics", "How it moves: the dynamic checks", "".join(_table(t) for t in model.dynamics)))
    electrical = ""
    if model.regen is not None:
        electrical += _figure(model.regen, plot(model.regen))
    if model.electrical is not None:
        electrical += _table(model.electrical)
    if electrical:
        sections.append(("electrical", "Drive and regeneration", electrical))
    selection = ""
    if model.candidates is not None:
        selection += _table(model.candidates)
    if model.ratios is not None:
        selection += _table(model.ratios)
    if selection:
        sections.append(("selection", "Selection and ratio", selection))
    if model.order:
        sections.append(("order", "Order sheet", "".join(_table(t) for t in model.order)))
    sections.append(("inputs", "Inputs", _table(model.inputs, "dt-inputs")))
    formulas = "".join(_formula(f) for f in model.formulas)
    sections.append(("formulas", "Formulas and sources",
                     '<p class="dt-note">Each formula this sizing used, with its source and the function that '
                     f'implements it.</p><ol class="dt-formulas">{formulas}</ol>'))
    toc = " ".join(f'<a href="#dt-{key}">{k}&nbsp;{e(title)}</a>' for k, (key, title, _) in enumerate(sections, 1))
    body = "".join(f'<section id="dt-{key}"><h2>{k} {e(title)}</h2>{content}</section>'
                   for k, (key, title, content) in enumerate(sections, 1))
    meta = "".join(f"<dt>{e(k)}</dt><dd>{e(v)}</dd>" for k, v in model.meta)
    checks = _table(model.checks) if model.checks is not None else ""
    notes = "".join(f"<li>{e(n)}</li>" for n in model.notes)
    return (
        '<div class="dt-report">'
        f'<header class="dt-head"><div class="dt-kicker">drivetrain · {e(model.title)}</div>'
        f'<div><h1 id="dt-axis-name">{e(model.axis_name)}</h1><p class="dt-sub">{e(model.subtitle)}</p></div>'
        f'<dl class="dt-meta">{meta}</dl></header>'
        f"{_verdict(model.verdict)}{_kpis(model.key_figures)}{checks}"
        f'<nav class="dt-toc">{toc}</nav>{body}'
        f'<footer class="dt-foot"><ul>{notes}</ul><div>{e(model.title)} · {e(model.axis_name)} · '
        f"{e(model.footer)}</div></footer></div>"
    )


def _plotly_div(spec: PlotSpec, figures: list[tuple[str, str]]) -> str:
    from drivetrain.report.plots import to_plotly

    div_id = f"dt-plot-{spec.key}"
    figures.append((div_id, to_plotly(spec).to_json()))
    return f'<div class="dt-plot" id="{div_id}" data-plot="{e(spec.key)}" style="height:{spec.height}px"></div>'


def _plot_script(figures: list[tuple[str, str]]) -> str:
    import plotly.offline

    calls = ",".join("[" + json.dumps(div) + "," + fig_json.replace("</", "<\\/") + "]" for div, fig_json in figures)
    return (f'<script type="text/javascript">{plotly.offline.get_plotlyjs()}</script>\n'
            '<script type="text/javascript">(function(){'
            f"var cfg={json.dumps(PLOTLY_CONFIG)};var figs=[{calls}];"
            "figs.forEach(function(f){Plotly.newPlot(f[0],f[1].data,f[1].layout,cfg);});})();</script>")


def render_html(result: SizingResult, units: str = "si") -> str:
    """The whole report as one HTML document: offline, plotly.js embedded, every user string escaped."""
    from drivetrain.version import __version__

    model = build_report(result, units)
    figures: list[tuple[str, str]] = []
    body = render_body(model, lambda spec: _plotly_div(spec, figures))
    page = Template(_resource("report.html"))
    return page.substitute(version=e(__version__), title=e(f"{model.axis_name} · {model.title}"),
                           css=_resource("report.css"), body=body, scripts=_plot_script(figures))


_SVG_HEAD = re.compile(r"^.*?(<svg\b)", re.S)


def _static_plot(spec: PlotSpec) -> str:
    import io

    import matplotlib

    from drivetrain.report.plots import to_matplotlib

    fig = to_matplotlib(spec, width_in=9.0)
    buf = io.StringIO()
    with matplotlib.rc_context({"svg.fonttype": "none", "svg.hashsalt": "drivetrain"}):
        fig.savefig(buf, format="svg")
    svg = _SVG_HEAD.sub(r"\1", buf.getvalue(), count=1)
    svg = re.sub(r'<svg\b([^>]*?)\swidth="[^"]*"\s+height="[^"]*"', r'<svg\1', svg, count=1)
    return f'<div class="dt-static-plot">{svg}</div>'


def repr_html(result: SizingResult, units: str = "si") -> str:
    """The report as an HTML fragment for Jupyter (``_repr_html_``): static SVG plots, no script."""
    model = build_report(result, units)
    body = render_body(model, _static_plot)
    return f"<style>{_resource('report.css')}</style>{body}"
