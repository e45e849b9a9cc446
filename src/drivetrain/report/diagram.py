"""The axis as a diagram: motor -> each transmission element -> mechanism -> load.

Each block carries its ratio, efficiency and inertia (its own, and reflected to the motor
shaft); each link between blocks carries the largest speed and torque on that shaft over the
cycle. One layout feeds two renderers: an inline SVG for the HTML and matplotlib patches for
the PDF, so both show the same picture.
"""

from __future__ import annotations

import html
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from drivetrain.report.display import DisplayUnits, fmt_number, pretty_powers

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from drivetrain.report.focus import Focus
    from drivetrain.sizing.result import SizingResult

BLOCK_COLORS: dict[str, str] = {
    "motor": "#1f4e79",
    "transmission": "#4f6d8f",
    "mechanism": "#6b5a8e",
    "load": "#7f6000",
}
"""Header colour of each kind of block."""

MECHANISM_NAMES: dict[str, str] = {
    "ball_screw": "Ball screw",
    "lead_screw": "Lead screw",
    "belt": "Belt axis",
    "timing_belt": "Timing belt axis",
    "conveyor": "Conveyor",
    "rack_pinion": "Rack and pinion",
    "roll": "Feed roll",
    "rotary": "Rotary table",
    "hoist": "Hoist drum",
    "chain": "Chain loop",
    "custom": "Custom mechanism",
}
"""Readable name of each mechanism type of the axis file."""

STAGE_NAMES: dict[str, str] = {
    "gearbox": "Gearbox",
    "belt": "Belt stage",
    "gear_pair": "Gear pair",
    "chain": "Chain stage",
    "coupling": "Coupling",
    "brake": "Brake",
    "clutch": "Clutch",
}

_LOAD_PARTS = ("load", "M_1", "fed material", "unbalanced")


@dataclass
class Block:
    """One element of the drive train as drawn."""

    kind: str
    title: str
    lines: list[str] = field(default_factory=list)
    foot: str = ""


@dataclass
class Diagram:
    """Blocks from the motor outward and the shaft between each pair (``links[k]`` after ``blocks[k]``)."""

    blocks: list[Block]
    links: list[list[str]]
    caption: str = ""


def is_load_part(name: str) -> bool:
    """Whether a mechanism inertia part belongs to the moved load (drawn in the load block)."""
    return any(p in name for p in _LOAD_PARTS)


def _eta(efficiency: float, back: float) -> str:
    text = f"η = {fmt_number(efficiency, 3)}"
    if not math.isclose(back, efficiency):
        text += f" (back {fmt_number(back, 3)})"
    return text


def _stage_kind(result: SizingResult, k: int) -> str:
    raw = result.axis.raw.get("transmission") or []
    entry = raw[k] if k < len(raw) and isinstance(raw[k], dict) else {}
    st = result.axis.transmission[k]
    name = STAGE_NAMES.get(st.kind, st.kind.replace("_", " ").capitalize())
    if st.kind == "gearbox":
        kind = entry.get("kind", "planetary")
        name += f" ({kind})" if isinstance(kind, str) else ""
    return name


def build_diagram(result: SizingResult, du: DisplayUnits, focus: Focus | None = None) -> Diagram:
    """The blocks and links of an axis, values in display units."""
    axis = result.axis
    mech = axis.mechanism
    j = "inertia"
    blocks: list[Block] = []
    up = 1.0  # product of the ratios between the motor and the current element
    if focus is not None:
        motor = focus.motor
        title = "Motor " + motor.name if len(motor.name) < 16 else motor.name
        blocks.append(Block("motor", title, [
            f"J_M = {du.fmt(motor.inertia, j)}",
            f"T_N = {du.fmt(motor.rated_torque, 'torque')}",
            f"T_max = {du.fmt(motor.peak_torque, 'torque')}",
            f"n_N = {du.fmt(motor.rated_speed, 'angular_speed')}",
            f"n_max = {du.fmt(motor.max_speed, 'angular_speed')}",
        ] + (["catalog selection"] if focus.origin == "selection" else []),
            f"J_L / J_M = {fmt_number(focus.inertia_ratio, 3)}"))
        if focus.gearbox is not None:
            gb = focus.gearbox
            blocks.append(Block("transmission", "Gearbox (catalog)", [
                gb.id, f"i = {fmt_number(gb.ratio)}", _eta(gb.efficiency, gb.efficiency),
                f"J = {du.fmt(gb.inertia, j)}"], f"at motor {du.fmt(gb.inertia, j)}"))
            up = gb.ratio
    else:
        blocks.append(Block("motor", "Motor", ["not given:", "demand at its shaft only"],
                            f"J_L = {du.fmt(result.duty.load_inertia, j)}"))
    for k, st in enumerate(axis.transmission):
        lines = []
        if st.kind not in ("coupling", "brake", "clutch") or st.ratio != 1.0:
            lines.append(f"i = {fmt_number(st.ratio)}")
        if st.kind not in ("coupling", "brake", "clutch"):
            lines.append(_eta(st.efficiency, st.back_efficiency))
        lines.append(f"J = {du.fmt(st.inertia, j)}")
        if st.holding_torque is not None:
            lines.append(f"holds {du.fmt(st.holding_torque, 'torque')}")
        blocks.append(Block("transmission", _stage_kind(result, k), lines,
                            f"at motor {du.fmt(st.inertia / up**2, j)}"))
        up *= st.ratio
    st = mech.stage
    parts = mech.inertia_parts or {"mechanism": st.inertia}
    own = {k: v for k, v in parts.items() if not is_load_part(k)}
    load_parts = {k: v for k, v in parts.items() if is_load_part(k)}
    lines = []
    if mech.motion == "linear":
        travel = 2.0 * math.pi / st.ratio
        lines.append(f"travel {du.fmt(travel, 'length')}/rev")
    elif st.ratio != 1.0:
        lines.append(f"i = {fmt_number(st.ratio)}")
    lines.append(_eta(st.efficiency, st.back_efficiency))
    for name, value in own.items():
        if value:
            lines.append(f"{pretty_powers(name)}: {du.fmt(value, j)}")
    blocks.append(Block("mechanism", MECHANISM_NAMES.get(mech.type, mech.type), lines,
                        f"at motor {du.fmt(sum(own.values()) / up**2, j)}"))
    blocks.append(Block("load", "Load", _load_lines(result, du),
                        f"at motor {du.fmt(sum(load_parts.values()) / up**2, j)}"))
    links = _links(result, du, focus)
    caption = ("From the motor outward: ratio i (input / output speed), efficiency η (back: when the load drives), "
               "each element's own inertia J and its share of the load inertia at the motor shaft. "
               "On each shaft: the largest speed and torque over the cycle (motor shaft: without the rotor's own "
               "acceleration torque).")
    return Diagram(blocks, links, caption)


def _load_lines(result: SizingResult, du: DisplayUnits) -> list[str]:
    from drivetrain.physics.mechanisms.base import LinearLoad

    load = result.axis.mechanism.load
    lines: list[str] = []
    if isinstance(load, LinearLoad):
        if load.mass or not (load.thrust or load.press_force):
            lines.append(f"M = {du.fmt(load.mass, 'mass')}")
        if load.counterweight:
            lines.append(f"counterweight {du.fmt(load.counterweight, 'mass')}")
        if load.incline:
            lines.append(f"incline {fmt_number(math.degrees(load.incline), 3)}°")
        if load.friction:
            lines.append(f"μ = {fmt_number(load.friction, 3)}")
        if load.thrust:
            lines.append(f"thrust {du.fmt(load.thrust, 'force')}")
        if load.press_force:
            lines.append(f"normal force {du.fmt(load.press_force, 'force')}")
    else:
        if load.inertia:
            lines.append(f"J = {du.fmt(load.inertia, 'inertia')}")
        if load.unbalance_mass:
            lines.append(f"unbalance {du.fmt(load.unbalance_mass, 'mass')} "
                         f"at {du.fmt(load.unbalance_radius, 'length')}")
        if load.incline:
            lines.append(f"axis tilt {fmt_number(math.degrees(load.incline), 3)}°")
        if load.torque:
            lines.append(f"torque {du.fmt(load.torque, 'torque')}")
        if load.friction_torque:
            lines.append(f"friction {du.fmt(load.friction_torque, 'torque')}")
    return lines or ["(no load data)"]


def _links(result: SizingResult, du: DisplayUnits, focus: Focus | None) -> list[list[str]]:
    duty = result.duty
    stages = result.axis.stages
    out = []
    if focus is not None and focus.gearbox is not None:
        out.append([f"≤ {du.fmt(float(np.max(np.abs(focus.omega))), 'angular_speed')}",
                    f"≤ {du.fmt(float(np.max(np.abs(focus.torque_load))), 'torque')}"])
    out.append([f"≤ {du.fmt(float(np.max(np.abs(duty.omega))), 'angular_speed')}",
                f"≤ {du.fmt(float(np.max(np.abs(duty.torque))), 'torque')}"])
    for k in range(len(stages) - 1):
        out.append([f"≤ {du.fmt(float(np.max(np.abs(duty.stage_omega[k]))), 'angular_speed')}",
                    f"≤ {du.fmt(float(np.max(np.abs(duty.stage_torque[k]))), 'torque')}"])
    w, t = np.abs(duty.stage_omega[-1]), np.abs(duty.stage_torque[-1])
    if result.axis.mechanism.motion == "linear":
        out.append([f"≤ {du.fmt(float(np.max(w)), 'speed')}", f"F ≤ {du.fmt(float(np.max(t)), 'force')}"])
    else:
        out.append([f"≤ {du.fmt(float(np.max(w)), 'angular_speed')}", f"T ≤ {du.fmt(float(np.max(t)), 'torque')}"])
    return out


# --------------------------------------------------------------------------- layout

BLOCK_W = 150.0
GAP_W = 74.0
PAD = 8.0
HEADER_H = 28.0
LINE_H = 17.0
FONT = 12.0
INSET = 9.0


@dataclass
class _Text:
    x: float
    y: float
    text: str
    size: float
    color: str = "#222"
    anchor: str = "start"
    bold: bool = False
    italic: bool = False


@dataclass
class _Layout:
    width: float
    height: float
    block_h: float
    xs: list[float]
    texts: list[_Text]


def _layout(d: Diagram) -> _Layout:
    """Positions and fitted font sizes of every text (SVG user units = points in the PDF, before scaling)."""
    from drivetrain.report.display import fit_text

    rows = max(len(b.lines) for b in d.blocks)
    block_h = HEADER_H + 10 + LINE_H * rows + LINE_H + 16
    n = len(d.blocks)
    xs = [PAD + k * (BLOCK_W + GAP_W) for k in range(n)]
    inner = BLOCK_W - 2 * INSET
    texts: list[_Text] = []
    y0 = PAD
    for k, (b, x) in enumerate(zip(d.blocks, xs, strict=True)):
        t, size = fit_text(b.title, FONT + 1, inner, bold=True)
        texts.append(_Text(x + BLOCK_W / 2, y0 + 19, t, size, "#fff", "middle", bold=True))
        for i, line in enumerate(b.lines):
            t, size = fit_text(line, FONT, inner)
            texts.append(_Text(x + INSET, y0 + HEADER_H + 10 + LINE_H * (i + 0.75), t, size))
        if b.foot:
            t, size = fit_text(b.foot, FONT - 1, inner)
            texts.append(_Text(x + INSET, y0 + block_h - 10 - 1, t, size, "#555", italic=True))
        if k < len(d.links):
            ax0, ax1 = x + BLOCK_W + 4, x + BLOCK_W + GAP_W - 6
            ym = y0 + block_h / 2
            for i, text in enumerate(d.links[k][:2]):
                t, size = fit_text(text, FONT - 1.5, GAP_W - 8)
                texts.append(_Text((ax0 + ax1) / 2, ym - 8 if i == 0 else ym + 18, t, size, "#333", "middle"))
    return _Layout(2 * PAD + n * BLOCK_W + (n - 1) * GAP_W, block_h + 2 * PAD, block_h, xs, texts)


def to_svg(d: Diagram) -> str:
    """The diagram as an inline SVG element (every text escaped)."""
    lay = _layout(d)
    e = html.escape
    out = [f'<svg class="dt-diagram" xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {lay.width:.0f} '
           f'{lay.height:.0f}" style="max-width:{lay.width * 1.15:.0f}px" role="img" aria-label="axis diagram" '
           'font-family="DejaVu Sans, Segoe UI, Helvetica, Arial, sans-serif">',
           '<defs><marker id="dt-arrow" viewBox="0 0 10 10" refX="9" refY="5" markerWidth="7" markerHeight="7" '
           'orient="auto-start-reverse"><path d="M0,0 L10,5 L0,10 z" fill="#444"/></marker></defs>']
    y0 = PAD
    for k, (b, x) in enumerate(zip(d.blocks, lay.xs, strict=True)):
        color = BLOCK_COLORS.get(b.kind, "#444")
        out.append(f'<g class="dt-block dt-{e(b.kind)}"><title>{e(b.title)}</title>')
        out.append(f'<rect x="{x:.1f}" y="{y0:.1f}" width="{BLOCK_W:.0f}" height="{lay.block_h:.1f}" rx="6" '
                   f'fill="#fff" stroke="{color}" stroke-width="1.5"/>')
        out.append(f'<path d="M{x:.1f},{y0 + HEADER_H:.1f} v{-HEADER_H + 6:.1f} q0,-6 6,-6 h{BLOCK_W - 12:.1f} '
                   f'q6,0 6,6 v{HEADER_H - 6:.1f} z" fill="{color}"/>')
        if b.foot:
            fy = y0 + lay.block_h - 10 - LINE_H
            out.append(f'<line x1="{x + 8:.1f}" y1="{fy:.1f}" x2="{x + BLOCK_W - 8:.1f}" y2="{fy:.1f}" '
                       f'stroke="#ddd"/>')
        out.append("</g>")
        if k < len(d.links):
            ax0, ax1 = x + BLOCK_W + 4, x + BLOCK_W + GAP_W - 6
            ym = y0 + lay.block_h / 2
            out.append(f'<line x1="{ax0:.1f}" y1="{ym:.1f}" x2="{ax1:.1f}" y2="{ym:.1f}" stroke="#444" '
                       f'stroke-width="1.6" marker-end="url(#dt-arrow)"/>')
    for t in lay.texts:
        style = (' font-weight="bold"' if t.bold else "") + (' font-style="italic"' if t.italic else "")
        out.append(f'<text x="{t.x:.1f}" y="{t.y:.1f}" text-anchor="{t.anchor}" font-size="{t.size:.2f}" '
                   f'fill="{t.color}"{style}>{e(t.text)}</text>')
    out.append("</svg>")
    return "".join(out)


def draw_matplotlib(d: Diagram, fig: Figure, rect: tuple[float, float, float, float]) -> None:
    """Draw the diagram into ``rect`` of ``fig`` (figure fractions), same layout as the SVG."""
    from matplotlib.patches import FancyBboxPatch

    from drivetrain.report.plots import mpl_text

    lay = _layout(d)
    left, bottom, width, height = rect
    fig_w, fig_h = fig.get_size_inches()
    scale_in = min(width * fig_w / lay.width, height * fig_h / lay.height)  # inches per layout unit
    w_frac, h_frac = lay.width * scale_in / fig_w, lay.height * scale_in / fig_h
    ax = fig.add_axes((left + (width - w_frac) / 2, bottom + (height - h_frac) / 2, w_frac, h_frac))
    ax.set_xlim(0, lay.width)
    ax.set_ylim(lay.height, 0)
    ax.axis("off")
    pt = scale_in * 72.0  # points per layout unit
    y0 = PAD
    for k, (b, x) in enumerate(zip(d.blocks, lay.xs, strict=True)):
        color = BLOCK_COLORS.get(b.kind, "#444")
        ax.add_patch(FancyBboxPatch((x, y0), BLOCK_W, lay.block_h, boxstyle="round,pad=0,rounding_size=6",
                                    fc="white", ec=color, lw=1.1))
        ax.add_patch(FancyBboxPatch((x, y0), BLOCK_W, HEADER_H, boxstyle="round,pad=0,rounding_size=6",
                                    fc=color, ec=color, lw=1.1))
        if b.foot:
            fy = y0 + lay.block_h - 10 - LINE_H
            ax.plot([x + 8, x + BLOCK_W - 8], [fy, fy], color="#dddddd", lw=0.6)
        if k < len(d.links):
            ax0, ax1 = x + BLOCK_W + 4, x + BLOCK_W + GAP_W - 6
            ym = y0 + lay.block_h / 2
            ax.annotate("", xy=(ax1, ym), xytext=(ax0, ym),
                        arrowprops={"arrowstyle": "-|>", "color": "#444", "lw": 1.1})
    for t in lay.texts:
        ax.text(t.x, t.y, mpl_text(t.text), ha={"start": "left", "middle": "center"}.get(t.anchor, "left"),
                va="baseline", fontsize=t.size * pt, color=t.color, fontweight="bold" if t.bold else "normal",
                fontstyle="italic" if t.italic else "normal")


def aspect(d: Diagram) -> float:
    """Height / width of the drawn diagram."""
    lay = _layout(d)
    return lay.height / lay.width
