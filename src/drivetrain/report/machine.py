"""The machine report: the DC bus over the machine cycle, the buses, phasing, the bill of materials, each axis's page.

HTML: one self-contained file (plotly.js embedded, every user string escaped), built from the
axis report's blocks (``report.html``: tables, verdict, key figures, plots) with each axis's own
report body below the machine's. PDF: the same content on A4 pages through the axis report's
layout engine (``report.pdf``).
"""

from __future__ import annotations

import html
import os
from dataclasses import replace
from pathlib import Path
from string import Template
from types import SimpleNamespace
from typing import TYPE_CHECKING, Any

import numpy as np

from drivetrain.errors import InputError
from drivetrain.report.blocks import Cell, KeyFigure, Table, Verdict
from drivetrain.report.display import fmt_number
from drivetrain.report.model import ReportModel, build_report, report_date
from drivetrain.report.plots import Panel, PlotSpec, Trace

if TYPE_CHECKING:
    from drivetrain.machine.result import MachineResult

e = html.escape
COLORS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22")
TITLE = "Machine sizing report"


def _w(x: float | None) -> str:
    return "-" if x is None else f"{fmt_number(x)} W"


def _j(x: float | None) -> str:
    return "-" if x is None else f"{fmt_number(x)} J"


def bus_plot(result: MachineResult) -> PlotSpec:
    """Each axis's electrical power and each bus's sum over one machine cycle [W]."""
    t = np.asarray(result.grid, dtype=float)
    axes_panel = Panel("axis power [W]")
    bus_panel = Panel("bus power [W]")
    k = 0
    for bus, traces in result.traces.items():
        for name, p in traces.items():
            if name == "bus":
                bus_panel.traces.append(Trace(t, np.asarray(p), f"{bus}", COLORS[k % len(COLORS)], width=2.2))
            else:
                axes_panel.traces.append(Trace(t, np.asarray(p), name, COLORS[k % len(COLORS)]))
            k += 1
    return PlotSpec("bus", "DC-bus power over the machine cycle", "time [s]", [axes_panel, bus_panel],
                    caption="Positive: drawn from the bus (motoring); negative: fed into it (braking). Each axis at "
                            "its start in the machine cycle; free axes at offset 0.", height=560)


def _verdict(result: MachineResult, d: dict[str, Any]) -> Verdict:
    details = [f"axis {a['name']} fails: " + "; ".join(
        (r.get("motor") or {}).get("failed", "") or "a check fails" for r in
        ([a["result"]] if "result" in a else a["results"])) for a in d["axes"] if not a["ok"]]
    for b in d["buses"]:
        if not b.get("ok", True):
            details.append(f"bus {b['name']}: its supply module or braking resistors do not suffice")
        if b["resistor_needed"] and not b.get("resistors"):
            details.append(f"bus {b['name']} needs a braking resistor: "
                           f"{_j(b['resistor_energy_per_cycle_J'])} per cycle,"
                           f" {_w(b['resistor_average_power_W'])} average, {_w(b['resistor_peak_power_W'])} peak")
    unknown = [f"Not judged (axis {u['axis']}, {u['part']}): {u['check']}: {u['decide']}." for u in result.unknowns()]
    if result.status == "pass":
        return Verdict("pass", f"Every axis of {d['machine']['name']} passes", details)
    if result.status == "pass with unknowns":
        return Verdict("unknowns", f"{d['machine']['name']}: pass with unknowns "
                       f"({len(unknown)} not judged)", details + unknown)
    return Verdict("fail", f"{d['machine']['name']} does not pass", details + unknown)


def _key_figures(d: dict[str, Any]) -> list[KeyFigure]:
    m = d["machine"]
    return [
        KeyFigure("Bus peak power", _w(m["bus_peak_power_W"]), "motoring, all buses"),
        KeyFigure("Bus RMS power", _w(m["bus_rms_power_W"]), "over the machine cycle"),
        KeyFigure("Regen shared", _j(m["regen_shared_J"]), "braking -> motoring axes, per cycle"),
        KeyFigure("Resistor energy", _j(m["resistor_energy_per_cycle_J"]), "per cycle"),
        KeyFigure("Resistor peak", _w(m["resistor_peak_power_W"]), f"average {_w(m['resistor_average_power_W'])}"),
        KeyFigure("Supply peak", _w(m["supply_peak_power_W"]), f"continuous {_w(m['supply_continuous_power_W'])}"),
        KeyFigure("Supply current", f"{fmt_number(m['supply_peak_current_A'])} A",
                  f"peak, {m['supply_voltage_V']:.0f} V {m['supply_phases']}-phase"),
        KeyFigure("Cycle time", f"{fmt_number(m['cycle_time_s'])} s", f"{len(d['axes'])} axes"),
    ]


def _axes_table(d: dict[str, Any]) -> Table:
    rows = []
    for a in d["axes"]:
        shares = " + ".join(f"{s * 100:.0f} %" for s in a["load_shares"]) if a["motors"] > 1 else "1"
        rows.append([Cell(a["name"], "strong"), Cell(a["source"]), Cell(shares), Cell(f"{fmt_number(a['offset_s'])} s"),
                     Cell(a["phasing"]), Cell(a["power_basis"]), Cell(_w(a["peak_power_W"])),
                     Cell(_j(a["regen_energy_J"])), Cell("pass" if a["ok"] else "FAIL", "pass" if a["ok"] else "fail")])
    notes = sorted({n for a in d["axes"] for n in a["notes"]})
    return Table("machine-axes", "Axes", ["axis", "file", "motors", "start", "phasing", "power basis", "peak power",
                                          "regen", "verdict"], rows, "lllrllrrl", note=" ".join(notes),
                 widths=[0.7, 1.3, 0.9, 0.7, 0.8, 0.9, 0.9, 0.8, 0.7])


def _bus_table(d: dict[str, Any]) -> Table:
    keys = [("bus_peak_power_W", "bus peak power", _w), ("bus_peak_regen_power_W", "bus peak regenerative power", _w),
            ("bus_rms_power_W", "bus RMS power", _w), ("regen_into_bus_J", "braking energy of the axes", _j),
            ("regen_shared_J", "shared with motoring axes", _j),
            ("capacitor_energy_per_event_J", "capacitors per event", _j),
            ("capacitor_absorbed_J", "capacitors absorb", _j),
            ("resistor_energy_per_cycle_J", "braking resistor energy per cycle", _j),
            ("resistor_peak_power_W", "braking resistor peak power", _w),
            ("resistor_average_power_W", "braking resistor average power", _w),
            ("resistor_min_ohm", "resistance at least", lambda x: "not given" if x is None else f"{fmt_number(x)} ohm"),
            ("resistor_max_ohm", "resistance at most", lambda x: "not known" if x is None else f"{fmt_number(x)} ohm"),
            ("supply_peak_power_W", "supply peak power", _w),
            ("supply_continuous_power_W", "supply continuous power", _w),
            ("supply_peak_current_A", "supply peak line current", lambda x: f"{fmt_number(x)} A"),
            ("supply_rms_current_A", "supply RMS line current", lambda x: f"{fmt_number(x)} A")]
    rows = [[Cell(label)] + [Cell(fmt(b.get(k))) for b in d["buses"]] for k, label, fmt in keys]
    return Table("machine-buses", "DC buses", ["quantity", *[b["name"] for b in d["buses"]]], rows,
                 "l" + "r" * len(d["buses"]),
                 note="Supply current at the stated power factor (supply.power_factor, default 1). The resistance "
                      "window needs the drives' minimum resistance and chopper switch-on voltage.")


def _phasing_table(d: dict[str, Any]) -> Table | None:
    ph = d.get("phasing")
    if not ph:
        return None
    labels = {"bus_peak_power_W": ("bus peak power", _w), "bus_rms_power_W": ("bus RMS power", _w),
              "supply_peak_power_W": ("supply peak power", _w),
              "resistor_energy_per_cycle_J": ("resistor energy per cycle", _j),
              "resistor_peak_power_W": ("resistor peak power", _w), "regen_shared_J": ("regen shared", _j)}
    rows = []
    for k, (label, fmt) in labels.items():
        r = ph["random"][k]
        rows.append([Cell(label), Cell(fmt(ph["in_phase"][k])), Cell(fmt(r["p50"])), Cell(fmt(r["p95"])),
                     Cell(fmt(r["p100"]))])
    return Table("machine-phasing", f"Phasing of the free axes ({', '.join(ph['free_axes'])})",
                 ["quantity", "all in phase", "random p50", "random p95", "random max"], rows, "lrrrr",
                 note=f"{ph['samples']} random phasings, seed {ph['seed']}: {ph['method']}.")


def _bom_table(d: dict[str, Any]) -> Table:
    rows = [[Cell(r["kind"].replace("_", " ")), Cell(str(r["order_code"] or r.get("note", "-")), "strong"),
             Cell(str(r["vendor"] or "-")), Cell(str(r["quantity"])), Cell(", ".join(r["used_by"]))]
            for r in d["bill_of_materials"]]
    return Table("machine-bom", "Bill of materials", ["item", "order code", "vendor", "qty", "used by"], rows, "lllrl")


def _axis_models(result: MachineResult) -> list[tuple[str, ReportModel]]:
    out = []
    for a in result.machine.axes:
        ap = result.axes[a.name]
        for k, r in enumerate(ap.results):
            label = a.name if a.motors == 1 else f"{a.name}, motor {k + 1} ({a.shares[k] * 100:.0f} % of the load)"
            model = build_report(r)
            model.axis_name = f"{label}: {model.axis_name}"
            out.append((label, model))
    return out


def render_machine_html(result: MachineResult) -> str:
    """The machine report as one offline HTML document."""
    from drivetrain.report.html import _kpis, _plot_script, _plotly_div, _resource, _table, render_body
    from drivetrain.report.html import _verdict as verdict_html
    from drivetrain.version import __version__

    d = result.to_dict()
    figures: list[tuple[str, str]] = []
    spec = bus_plot(result)
    parts = [f'<figure class="dt-figure" id="dt-fig-bus">{_plotly_div(spec, figures)}'
             f"<figcaption>{e(spec.caption)}</figcaption></figure>", _table(_bus_table(d))]
    ph = _phasing_table(d)
    sections = [("machine-bus", "DC bus over the machine cycle", "".join(parts)),
                ("machine-axes", "Axes", _table(_axes_table(d)))]
    if ph is not None:
        sections.append(("machine-phasing", "Phasing", _table(ph)))
    sections.append(("machine-bom", "Bill of materials", _table(_bom_table(d))))
    axis_html = []
    for k, (label, model) in enumerate(_axis_models(result), 1):
        def plot(s: PlotSpec, k: int = k) -> str:
            return _plotly_div(replace(s, key=f"a{k}-{s.key}"), figures)

        axis_html.append(f'<section class="dt-machine-axis" id="dt-machine-axis-{k}">'
                         f"{render_body(model, plot)}</section>")
        sections.append((f"machine-axis-{k}", f"Axis {label}", ""))
    toc = "".join(f'<a href="#dt-{key}">{n}&nbsp;{e(title)}</a>' for n, (key, title, _) in enumerate(sections, 1))
    body = "".join(f'<section id="dt-{key}"><h2>{n} {e(title)}</h2>{content}</section>'
                   for n, (key, title, content) in enumerate(sections, 1) if content)
    date = report_date()
    m = d["machine"]
    meta = [("Date", date), ("Software", f"drivetrain {__version__}"),
            ("Cycle time", f"{fmt_number(m['cycle_time_s'])} s"),
            ("Supply", f"{m['supply_voltage_V']:.0f} V, {m['supply_phases']} phases")]
    meta_html = "".join(f"<dt>{e(k)}</dt><dd>{e(v)}</dd>" for k, v in meta)
    page = (
        '<div class="dt-report">'
        f'<header class="dt-head"><div class="dt-kicker">drivetrain · {e(TITLE)}</div>'
        f'<div><h1 id="dt-machine-name">{e(m["name"])}</h1><p class="dt-sub">{len(d["axes"])} axes, '
        f'{len(d["buses"])} DC bus(es)</p></div><dl class="dt-meta">{meta_html}</dl></header>'
        f"{verdict_html(_verdict(result, d))}{_kpis(_key_figures(d))}"
        f'<nav class="dt-toc">{toc}</nav>{body}'
        f'<footer class="dt-foot"><div>{e(TITLE)} · {e(m["name"])} · drivetrain {e(__version__)} · {e(date)}</div>'
        "</footer></div>" + "".join(axis_html))
    return Template(_resource("report.html")).substitute(
        version=e(__version__), title=e(f"{m['name']} · {TITLE}"), css=_resource("report.css"), body=page,
        scripts=_plot_script(figures))


def render_machine_pdf(result: MachineResult, path: Path) -> None:
    """The machine report on A4 pages: the machine's sections, then a page set per axis."""
    import matplotlib

    from drivetrain.report.pdf import INK, _Doc
    from drivetrain.version import __version__

    d = result.to_dict()
    m = d["machine"]
    date = report_date()
    head = SimpleNamespace(title=TITLE, axis_name=m["name"], subtitle=f"{len(d['axes'])} axes", footer=(
        f"drivetrain {__version__} · {date}"), meta=[("Date", date), ("Software", f"drivetrain {__version__}"),
                                                    ("Cycle time", f"{fmt_number(m['cycle_time_s'])} s"),
                                                    ("Supply", f"{m['supply_voltage_V']:.0f} V")])
    with matplotlib.rc_context({"pdf.fonttype": 42, "font.family": "DejaVu Sans", "mathtext.fontset": "dejavusans",
                                "axes.titlesize": 8, "axes.labelcolor": INK, "text.color": INK}):
        doc = _Doc(f"{m['name']} · {TITLE}")
        doc.title_block(head)  # type: ignore[arg-type]
        doc.verdict(_verdict(result, d))
        doc.key_figures(_key_figures(d))
        doc.heading("1 DC bus over the machine cycle")
        doc.plot(bus_plot(result), 4.6)
        doc.table(_bus_table(d))
        doc.heading("2 Axes")
        doc.table(_axes_table(d))
        n = 3
        ph = _phasing_table(d)
        if ph is not None:
            doc.heading(f"{n} Phasing")
            doc.table(ph)
            n += 1
        doc.heading(f"{n} Bill of materials")
        doc.table(_bom_table(d))
        for label, model in _axis_models(result):
            n += 1
            doc.flush()
            doc.title_block(model)
            doc.verdict(model.verdict)
            doc.key_figures(model.key_figures)
            if model.checks is not None:
                doc.table(model.checks)
            doc.heading(f"{n} Axis {label}: motor shaft")
            doc.plot(model.motor_shaft, 4.2)
            doc.table(model.demand)
            doc.heading(f"{n} Axis {label}: speed-torque plane")
            doc.plot(model.speed_torque, 4.3)
            if model.motor_data is not None:
                doc.table(model.motor_data)
        doc.finish(path, head)  # type: ignore[arg-type]


def write_machine_report(result: MachineResult, path: str | os.PathLike[str]) -> Path:
    """Write the machine report as HTML (``.html``) or PDF (``.pdf``); the file is replaced only when complete."""
    from drivetrain.files import write_atomic

    target = Path(path)
    suffix = target.suffix.lower()
    if suffix not in (".html", ".htm", ".pdf"):
        raise InputError("--report", "must end in .html or .pdf", str(path))
    if suffix == ".pdf":
        return write_atomic(target, lambda tmp: render_machine_pdf(result, tmp), "--report")
    data = render_machine_html(result).encode("utf-8")

    def write(tmp: Path) -> None:
        tmp.write_bytes(data)

    return write_atomic(target, write, "--report")
