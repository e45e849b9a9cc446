"""The report's plots, described once and drawn by plotly (HTML, interactive) or matplotlib (PDF, static).

A builder turns a ``SizingResult`` into a :class:`PlotSpec` (panels of traces, phase bands,
vertical limit lines and annotations, all in display units); :func:`to_plotly` and
:func:`draw_matplotlib` draw the same spec with the same colours, labels and data. plotly and
matplotlib are imported inside the renderers only.

Plots: the load's motion (position, speed, acceleration, jerk), the motor shaft's speed and
torque with the phases shaded and RMS and peak marked, and the speed-torque plane with the
motor's envelopes, the cycle's operating points, the RMS point at mean speed and the margins.
"""

from __future__ import annotations

import html
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import NDArray

from drivetrain.report.display import DisplayUnits, fmt_number, fmt_percent

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from plotly.graph_objects import Figure as PlotlyFigure

    from drivetrain.report.focus import Focus
    from drivetrain.sizing.result import SizingResult

Array = NDArray[np.float64]

COLORS: dict[str, str] = {
    "position": "#1f4e79",
    "speed": "#c55a11",
    "acceleration": "#38761d",
    "jerk": "#7f6000",
    "motor_torque": "#1f4e79",
    "load_torque": "#6fa8dc",
    "rms": "#7b1fa2",
    "peak": "#c62828",
    "continuous": "#2e7d32",
    "intermittent": "#c62828",
    "operating": "#1f4e79",
    "limit": "#555555",
}
"""One colour per quantity, shared by every plot, both renderers and the report's CSS."""

PHASE_COLORS: dict[str, str] = {"accel": "#b7dfb9", "run": "#c6d9f1", "decel": "#f9cfae", "dwell": "#dcdcdc"}
"""Background of each phase of the cycle (accel, run, decel, dwell)."""
BAND_OPACITY = 0.45
FONT_FAMILY = "DejaVu Sans, Segoe UI, Helvetica Neue, Arial, sans-serif"

Dash = Literal["solid", "dash", "dot"]
Mode = Literal["lines", "markers", "lines+markers"]
Marker = Literal["circle", "diamond", "square", "x"]


@dataclass
class Trace:
    """A data series: x and y in display units, its legend name and style."""

    x: Array
    y: Array
    name: str
    color: str
    dash: Dash = "solid"
    width: float = 1.8
    mode: Mode = "lines"
    marker: Marker = "circle"
    size: float = 7.0
    legend: bool = True
    unit: str = ""


@dataclass
class Band:
    """A shaded span of the x axis: one phase of the cycle."""

    x0: float
    x1: float
    kind: str


@dataclass
class VLine:
    """A vertical limit line (e.g. the motor's maximum speed)."""

    x: float
    name: str
    color: str
    dash: Dash = "dash"


@dataclass
class Note:
    """An annotation with an arrow to (x, y); the text box sits ``dx``, ``dy`` points away (dy up)."""

    x: float
    y: float
    lines: list[str]
    color: str
    dx: float = 40.0
    dy: float = 30.0


@dataclass
class Panel:
    """One y axis of a figure: traces over shared x, with bands, limit lines and notes."""

    ylabel: str
    traces: list[Trace] = field(default_factory=list)
    bands: list[Band] = field(default_factory=list)
    vlines: list[VLine] = field(default_factory=list)
    notes: list[Note] = field(default_factory=list)
    ymin: float | None = None


@dataclass
class PlotSpec:
    """A figure: stacked panels sharing the x axis. ``height`` is in CSS pixels for the HTML."""

    key: str
    title: str
    xlabel: str
    panels: list[Panel]
    caption: str = ""
    height: int = 480
    phase_legend: bool = False
    hover: Literal["x unified", "closest"] = "x unified"
    xrange: tuple[float, float] | None = None


# --------------------------------------------------------------------------- builders


def _phase_bands(result: SizingResult) -> list[Band]:
    return [Band(float(ph.t0), float(ph.t1), ph.kind) for ph in result.duty.cycle.phases if ph.t1 > ph.t0]


def motion_plot(result: SizingResult, du: DisplayUnits) -> PlotSpec:
    """Position, speed, acceleration and jerk of the load over one cycle."""
    s = result.duty.samples
    t = result.duty.t
    linear = result.axis.mechanism.motion == "linear"
    qs = ("length", "speed", "acceleration", "jerk") if linear else (
        "angle", "angular_speed", "angular_acceleration", "angular_jerk")
    names = ("position", "speed", "acceleration", "jerk")
    data = (s.x, s.v, s.a, s.j)
    bands = _phase_bands(result)
    panels = []
    for name, q, y in zip(names, qs, data, strict=True):
        label = du.label(q)
        panels.append(Panel(f"{name} [{label}]", [Trace(t, du.array(y, q), f"load {name}", COLORS[name],
                                                        unit=label)], bands=bands))
    shapes = {st.shape for st in result.duty.cycle.steps}
    caption = (f"Motion of the load over one cycle (t_c = {fmt_number(result.duty.period)} s), "
               "phases shaded: accel, run, decel, dwell.")
    if shapes & {"trapezoid", "triangle"}:
        caption += " A trapezoid's jerk is impulsive at its corners and is drawn as 0."
    return PlotSpec("motion", "Motion profile of the load", "time [s]", panels, caption, height=640,
                    phase_legend=True, xrange=(0.0, float(result.duty.period)))


def motor_shaft_plot(result: SizingResult, du: DisplayUnits, focus: Focus | None = None) -> PlotSpec:
    """Motor-shaft speed and torque over the cycle, phases shaded, RMS and peak marked."""
    duty = result.duty
    t = duty.t
    tq = du.label("torque")
    bands = _phase_bands(result)
    torque_panel = Panel(f"torque [{tq}]", bands=bands)
    if focus is not None:
        speed = du.array(focus.omega, "angular_speed")
        main = du.array(focus.torque, "torque")
        rms = du.to(focus.metrics["rms_torque_Nm"], "torque")
        torque_panel.traces.append(Trace(t, main, "motor torque (with rotor)", COLORS["motor_torque"], unit=tq))
        torque_panel.traces.append(Trace(t, du.array(focus.torque_load, "torque"), "load torque (rotor excluded)",
                                         COLORS["load_torque"], dash="dash", width=1.4, unit=tq))
    else:
        speed = du.array(duty.omega, "angular_speed")
        main = du.array(duty.torque, "torque")
        rms = du.to(result.metrics.rms_torque_Nm, "torque")
        torque_panel.traces.append(Trace(t, main, "load torque at motor shaft (rotor excluded)",
                                         COLORS["motor_torque"], unit=tq))
    span = np.array([0.0, float(duty.period)])
    torque_panel.traces.append(Trace(span, np.array([rms, rms]), f"RMS {fmt_number(rms)} {tq}", COLORS["rms"],
                                     dash="dot", width=1.4, unit=tq))
    torque_panel.traces.append(Trace(span, np.array([-rms, -rms]), "−RMS", COLORS["rms"], dash="dot", width=1.4,
                                     legend=False, unit=tq))
    k = int(np.argmax(np.abs(main)))
    peak = float(main[k])
    torque_panel.traces.append(Trace(np.array([t[k]]), np.array([peak]), f"peak {fmt_number(abs(peak))} {tq}",
                                     COLORS["peak"], mode="markers", marker="diamond", size=9, unit=tq))
    torque_panel.notes.append(Note(float(t[k]), peak, [f"peak {fmt_number(peak)} {tq}",
                                                       f"at {fmt_number(float(t[k]), 3)} s"],
                                   COLORS["peak"], dx=45, dy=-25 if peak > 0 else 25))
    speed_panel = Panel(f"motor speed [{du.label('angular_speed')}]",
                        [Trace(t, speed, "motor speed", COLORS["speed"], unit=du.label("angular_speed"))],
                        bands=bands)
    if focus is None:
        what = "the load torque (no motor given)."
    else:
        what = f"the torque of motor {focus.label} with its rotor"
        what += " (through the gearbox)." if focus.gearbox is not None else "."
    caption = ("Motor-shaft speed and torque over one cycle. Torque is positive in the direction of positive "
               f"motion; the RMS lines and the peak marker refer to {what}")
    return PlotSpec("motor", "Motor shaft: speed and torque over the cycle", "time [s]", [speed_panel, torque_panel],
                    caption, height=520, phase_legend=True, xrange=(0.0, float(duty.period)))


def _check_line(check: dict[str, Any] | None, du: DisplayUnits, factor: float) -> str:
    if check is None or check.get("available") is None:
        return ""
    torque = check.get("unit") == "N*m"
    req = float(check["required"]) * (du.factor("torque") if torque else 1.0)
    avail = float(check["available"]) * (du.factor("torque") if torque else 1.0)
    unit = du.label("torque") if torque else check.get("unit", "")
    sign = "≤" if check["ok"] else ">"
    head = f"×{fmt_number(factor, 3)} = " if factor != 1.0 else ""
    return f"{head}{fmt_number(req)} {sign} {fmt_number(avail)} {unit}: {fmt_percent(check.get('margin'))}"


def speed_torque_plot(result: SizingResult, du: DisplayUnits, focus: Focus | None = None,
                      supply: Sequence[Trace] = ()) -> PlotSpec:
    """The speed-torque plane: envelopes of the motor, the cycle's operating points, RMS point, margins;
    ``supply``: the motor's curves at the supply voltage (``electrical.supply_curve_traces``), if computed."""
    from drivetrain.units import from_rpm

    tq = du.label("torque")
    rpm = du.label("angular_speed")
    panel = Panel(f"|torque| [{tq}]", ymin=0.0)
    margins = result.axis.spec.motor.margins if result.axis.spec.motor is not None else None
    caption = ("Operating points of the cycle as magnitudes (the envelope is the same in every quadrant); "
               "the RMS torque is plotted at the mean speed, where the continuous envelope is checked.")
    if focus is not None:
        from drivetrain.sizing.envelope import continuous_torque, intermittent_torque

        motor = focus.motor
        w = np.unique(np.concatenate([np.linspace(0.0, motor.max_speed, 241), [motor.rated_speed]]))
        cont = continuous_torque(motor.rated_torque, motor.rated_speed, motor.max_speed, w, motor.stall_torque)
        peak = intermittent_torque(motor.peak_torque, motor.rated_torque, motor.rated_speed, motor.max_speed, w,
                                   motor.stall_torque)
        tag = " (approximate, derived from ratings)"
        x_env = du.array(w, "angular_speed")
        panel.traces.append(Trace(x_env, du.array(peak.torque[0], "torque"), f"intermittent{tag}",
                                  COLORS["intermittent"], width=2.2, unit=tq))
        panel.traces.append(Trace(x_env, du.array(cont.torque[0], "torque"), f"continuous S1{tag}",
                                  COLORS["continuous"], width=2.2, unit=tq))
        panel.traces.extend(supply)
        if supply:
            caption += (" The dashed and dotted purple curves are the motor's limits at the supply voltage, from "
                        "its electrical data (back-EMF, resistance, inductance) and the current limits.")
        n = du.array(np.abs(focus.omega), "angular_speed")
        main = du.array(np.abs(focus.torque), "torque")
        rms = focus.metrics["rms_torque_Nm"]
        mean_rpm = focus.metrics["mean_speed_rpm"]
        what = f"motor {focus.label}, with rotor"
        checks = {c["name"]: c for c in focus.checks}
        caption += (f" Envelopes of {focus.motor.name} are approximate, derived from its ratings (rated, stall and "
                    "peak torque, rated and maximum speed), as the checks use them: confirm thin margins on the "
                    "vendor's speed-torque curve.")
    else:
        n = du.array(np.abs(result.duty.omega), "angular_speed")
        main = du.array(np.abs(result.duty.torque), "torque")
        rms = result.metrics.rms_torque_Nm
        mean_rpm = result.metrics.mean_speed_rpm
        what = "load torque, rotor excluded"
        checks = {}
        caption += " No motor given: no envelope to compare with."
    panel.traces.append(Trace(n, main, f"cycle ({what})", COLORS["operating"], width=1.2, mode="lines+markers",
                              size=3.5, unit=tq))
    mean = du.to(from_rpm(mean_rpm), "angular_speed")
    rms_d = du.to(rms, "torque")
    panel.traces.append(Trace(np.array([mean]), np.array([rms_d]), "RMS at mean speed", COLORS["rms"],
                              mode="markers", marker="square", size=10, unit=tq))
    k = int(np.argmax(main))
    panel.traces.append(Trace(np.array([n[k]]), np.array([main[k]]), "peak", COLORS["peak"], mode="markers",
                              marker="diamond", size=10, unit=tq))
    f_t = margins.torque if margins else 1.0
    f_rms = (margins.rms_torque or margins.torque) if margins else 1.0
    peak_lines = [f"peak {fmt_number(float(main[k]))} {tq} at {fmt_number(float(n[k]))} {rpm}"]
    rms_lines = [f"RMS {fmt_number(rms_d)} {tq} at mean {fmt_number(mean)} {rpm}"]
    if checks:
        peak_lines.append(_check_line(checks.get("peak_torque"), du, f_t))
        rms_lines.append(_check_line(checks.get("rms_torque"), du, f_rms))
    x_max = float(np.max(n)) if n.size else 0.0
    panel.notes.append(Note(float(n[k]), float(main[k]), peak_lines, COLORS["peak"], dx=60, dy=18))
    panel.notes.append(Note(mean, rms_d, rms_lines, COLORS["rms"], dx=70, dy=-38))
    speed_check = checks.get("max_speed")
    name = f"max cycle speed {fmt_number(x_max)} {rpm}"
    if speed_check is not None and speed_check.get("margin") is not None:
        name += f" (margin {fmt_percent(speed_check['margin'])})"
    panel.vlines.append(VLine(x_max, name, COLORS["limit"]))
    if focus is not None and speed_check is not None and speed_check.get("available") is not None:
        limit = du.to(from_rpm(float(speed_check["available"])), "angular_speed")
        if limit < du.to(focus.motor.max_speed, "angular_speed") * (1 - 1e-9):
            panel.vlines.append(VLine(limit, f"speed limit {fmt_number(limit)} {rpm} (gearbox input)",
                                      COLORS["limit"], "dot"))
    return PlotSpec("speed_torque", "Speed-torque plane", f"|motor speed| [{rpm}]", [panel], caption, height=520,
                    hover="closest")


def all_plots(result: SizingResult, du: DisplayUnits, focus: Focus | None = None,
              supply: Sequence[Trace] = ()) -> list[PlotSpec]:
    """Every plot of the report, in report order (``supply``: see ``speed_torque_plot``)."""
    return [motion_plot(result, du), motor_shaft_plot(result, du, focus),
            speed_torque_plot(result, du, focus, supply)]


# --------------------------------------------------------------------------- plotly


def _plotly_text(text: str) -> str:
    """plotly renders a subset of HTML in labels: escape user text so it shows literally."""
    return html.escape(text, quote=False)


_PLOTLY_MARKER = {"circle": "circle", "diamond": "diamond", "square": "square", "x": "x"}


def to_plotly(spec: PlotSpec) -> PlotlyFigure:
    """The spec as an interactive plotly figure (SVG traces, no WebGL)."""
    import plotly.graph_objects as go
    from plotly.subplots import make_subplots

    rows = len(spec.panels)
    fig = make_subplots(rows=rows, cols=1, shared_xaxes=True, vertical_spacing=0.035 if rows > 2 else 0.07)
    for r, panel in enumerate(spec.panels, start=1):
        for band in panel.bands:
            fig.add_vrect(x0=band.x0, x1=band.x1, fillcolor=PHASE_COLORS.get(band.kind, "#eeeeee"),
                          opacity=BAND_OPACITY, layer="below", line_width=0, row=r, col=1,
                          exclude_empty_subplots=False)
        for tr in panel.traces:
            name = _plotly_text(tr.name)
            fig.add_trace(go.Scatter(
                x=tr.x, y=tr.y, name=name, mode=tr.mode, showlegend=tr.legend,
                line={"color": tr.color, "dash": tr.dash, "width": tr.width},
                marker={"color": tr.color, "symbol": _PLOTLY_MARKER[tr.marker], "size": tr.size},
                hovertemplate=f"%{{y:.4g}} {_plotly_text(tr.unit)}<extra>{name}</extra>",
            ), row=r, col=1)
        for v in panel.vlines:
            fig.add_vline(x=v.x, line={"color": v.color, "dash": v.dash, "width": 1.3}, row=r, col=1,
                          exclude_empty_subplots=False)
            fig.add_trace(go.Scatter(x=[None], y=[None], mode="lines", name=_plotly_text(v.name),
                                     line={"color": v.color, "dash": v.dash, "width": 1.3}), row=r, col=1)
        for note in panel.notes:
            fig.add_annotation(
                x=note.x, y=note.y, text="<br>".join(_plotly_text(s) for s in note.lines if s), showarrow=True,
                arrowhead=2, arrowsize=1, arrowwidth=1.2, arrowcolor=note.color, ax=note.dx, ay=-note.dy,
                align="left", font={"size": 11, "color": note.color}, bgcolor="rgba(255,255,255,0.88)",
                bordercolor=note.color, borderwidth=1, borderpad=3, row=r, col=1,
            )
        fig.update_yaxes(title_text=_plotly_text(panel.ylabel), row=r, col=1, zeroline=True,
                         zerolinecolor="#9a9a9a", zerolinewidth=1,
                         rangemode="tozero" if panel.ymin == 0.0 else "normal")
    fig.update_xaxes(title_text=_plotly_text(spec.xlabel), row=rows, col=1)
    if spec.xrange is not None:
        fig.update_xaxes(range=list(spec.xrange))
    if spec.phase_legend:
        for kind, color in PHASE_COLORS.items():
            fig.add_trace(go.Scatter(x=[None], y=[None], mode="markers", name=kind, hoverinfo="skip",
                                     marker={"symbol": "square", "size": 13, "color": color,
                                             "opacity": min(1.0, BAND_OPACITY + 0.35)}), row=1, col=1)
    fig.update_layout(
        template="plotly_white", height=spec.height, margin={"l": 70, "r": 24, "t": 46, "b": 52},
        font={"family": FONT_FAMILY, "size": 12, "color": "#222222"}, hovermode=spec.hover,
        legend={"orientation": "h", "yanchor": "bottom", "y": 1.01, "x": 0.0, "xanchor": "left",
                "font": {"size": 11}},
    )
    return fig


# --------------------------------------------------------------------------- matplotlib

_MPL_DASH = {"solid": "-", "dash": "--", "dot": ":"}
_MPL_MARKER = {"circle": "o", "diamond": "D", "square": "s", "x": "x"}


def mpl_text(text: str) -> str:
    """matplotlib treats ``$`` as mathtext: escape it in user text."""
    return text.replace("$", r"\$")


def draw_matplotlib(spec: PlotSpec, fig: Figure, rect: tuple[float, float, float, float],
                    fontsize: float = 7.5) -> None:
    """Draw the spec into ``rect`` = (left, bottom, width, height) of ``fig`` (figure fractions)."""
    from matplotlib.patches import Patch

    left, bottom, width, height = rect
    rows = len(spec.panels)
    legend_h = height * (0.11 if rows > 1 else 0.14)
    xlabel_h = height * 0.075
    gap = height * 0.02
    avail = height - legend_h - xlabel_h - gap * (rows - 1)
    ph = avail / rows
    axes: list[Axes] = []
    for r, panel in enumerate(spec.panels):
        y0 = bottom + xlabel_h + (rows - 1 - r) * (ph + gap)
        ax = fig.add_axes((left, y0, width, ph), sharex=axes[0] if axes else None)
        axes.append(ax)
        for band in panel.bands:
            ax.axvspan(band.x0, band.x1, color=PHASE_COLORS.get(band.kind, "#eeeeee"), alpha=BAND_OPACITY, lw=0,
                       zorder=0)
        for tr in panel.traces:
            has_line = tr.mode != "markers"
            has_marker = tr.mode != "lines"
            ax.plot(tr.x, tr.y, color=tr.color, lw=tr.width * 0.75 if has_line else 0,
                    ls=_MPL_DASH[tr.dash] if has_line else "none",
                    marker=_MPL_MARKER[tr.marker] if has_marker else None,
                    ms=tr.size * (0.55 if tr.mode == "markers" else 0.3),
                    label=mpl_text(tr.name) if tr.legend else "_nolegend_", zorder=3)
        for v in panel.vlines:
            ax.axvline(v.x, color=v.color, ls=_MPL_DASH[v.dash], lw=1.0, label=mpl_text(v.name), zorder=2)
        for note in panel.notes:
            text = "\n".join(mpl_text(s) for s in note.lines if s)
            ax.annotate(text, xy=(note.x, note.y), xytext=(note.dx * 0.75, note.dy * 0.75),
                        textcoords="offset points", fontsize=fontsize * 0.9, color=note.color,
                        ha="left", va="center", zorder=5,
                        bbox={"boxstyle": "round,pad=0.25", "fc": "white", "ec": note.color, "lw": 0.6,
                              "alpha": 0.92},
                        arrowprops={"arrowstyle": "->", "color": note.color, "lw": 0.8})
        ax.set_ylabel(mpl_text(panel.ylabel), fontsize=fontsize)
        ax.tick_params(labelsize=fontsize * 0.9, length=2.5)
        ax.grid(True, color="#e3e3e3", lw=0.5, zorder=1)
        ax.axhline(0.0, color="#9a9a9a", lw=0.6, zorder=1)
        if panel.ymin is not None:
            ax.set_ylim(bottom=panel.ymin)
        for side in ("top", "right"):
            ax.spines[side].set_visible(False)
        if r < rows - 1:
            ax.tick_params(labelbottom=False)
        ax.margins(x=0.0 if panel.bands else 0.02)
    axes[-1].set_xlabel(mpl_text(spec.xlabel), fontsize=fontsize)
    if spec.xrange is not None:
        axes[-1].set_xlim(*spec.xrange)
    handles: list[Any] = []
    seen: set[str] = set()
    for ax in axes:
        for h, lab in zip(*ax.get_legend_handles_labels(), strict=True):
            if lab not in seen:
                seen.add(lab)
                handles.append(h)
    if spec.phase_legend:
        handles += [Patch(facecolor=c, alpha=min(1.0, BAND_OPACITY + 0.35), label=k) for k, c in PHASE_COLORS.items()]
    if handles:
        ncol = max(1, min(len(handles), 4 if rows > 1 else 3))
        axes[0].legend(handles=handles, loc="lower left", bbox_to_anchor=(0.0, 1.01), ncol=ncol,
                       fontsize=fontsize * 0.88, frameon=False, handlelength=2.2, columnspacing=1.2,
                       borderaxespad=0.2)


def to_matplotlib(spec: PlotSpec, width_in: float = 9.0, dpi: float = 100.0) -> Figure:
    """The spec as a standalone matplotlib figure (no pyplot state)."""
    from matplotlib.figure import Figure

    height_in = width_in * figure_ratio(spec)
    fig = Figure(figsize=(width_in, height_in), dpi=dpi)
    draw_matplotlib(spec, fig, (0.085, 0.02, 0.885, 0.96), fontsize=9.0)
    return fig


def figure_ratio(spec: PlotSpec) -> float:
    """Height / width of the static figure for a spec."""
    return spec.height / 900.0 * 1.1
