"""Units and number formatting of the report: SI, imperial, or the units the axis file used.

Everything inside drivetrain is SI; the report converts once, here, with
:func:`drivetrain.units.convert` (rpm through the explicit 2 pi / 60 of ``units.to_rpm``).
A unit system maps each displayed quantity to a unit string that pint understands; labels are
the same strings made typographic ("N*m" -> "N·m", "kg*cm^2" -> "kg·cm²").
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from functools import lru_cache
from typing import TYPE_CHECKING, Any, Final, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from drivetrain.errors import InputError
from drivetrain.units import IMPERIAL_UNITS, SI_UNITS, UNIT_CHOICES

__all__ = ["ZERO_TOLERANCE", "DisplayUnits", "UnitsChoice", "display_units", "fmt_number", "fmt_percent",
           "pretty_unit", "snap_zero", "snapped_metrics"]

if TYPE_CHECKING:
    from matplotlib.ft2font import FT2Font

UnitsChoice = Literal["si", "imperial", "as-given"]

# Quantities tried, in order, when guessing what a unit string in the axis file measures.
_GUESS_ORDER: Final = ("length", "mass", "time", "inertia", "force", "speed", "angular_speed", "acceleration",
                       "angular_acceleration", "jerk", "angular_jerk", "angle", "power", "voltage")
_NUMBER_UNIT = re.compile(r"^\s*[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?\s*(?P<unit>\S.*?)\s*$")
_SUPERSCRIPT = str.maketrans("0123456789-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻")
_POUND_OUNCE = re.compile(r"(?<![A-Za-z_])(oz|lb)(?![A-Za-z_])")


def pretty_unit(unit: str) -> str:
    """Typographic form of a pint unit string: ``kg*cm^2`` -> ``kg·cm²``, ``N*m`` -> ``N·m``."""
    text = unit.strip().replace("**", "^").replace(" ", "").replace("*", "·")
    return re.sub(r"\^(-?\d+)", lambda m: m.group(1).translate(_SUPERSCRIPT), text)


def pretty_powers(text: str) -> str:
    """``r^2`` -> ``r²`` in labels taken from the code (inertia part names)."""
    return re.sub(r"\^(-?\d+)", lambda m: m.group(1).translate(_SUPERSCRIPT), text)


def fmt_number(value: float | None, sig: int = 4, signed: bool = False) -> str:
    """A number for a table: ``sig`` significant digits, no exponent between 1e-3 and 10**sig.

    Larger values are rounded to integers; smaller ones use ``×10ⁿ``. None and NaN give "—".
    """
    if value is None:
        return "—"
    v = float(value)
    if math.isnan(v):
        return "—"
    if math.isinf(v):
        return ("+" if signed and v > 0 else "-" if v < 0 else "") + "∞"
    sign = "+" if signed and v > 0 else ""
    a = abs(v)
    if a == 0.0:
        return "0"
    if a >= 10.0**sig:
        text = f"{v:.0f}"
    elif a >= 1e-3:
        text = f"{v:.{sig}g}"
        if "e" in text:  # e.g. 9999.5 rounds up to 1e+04
            text = f"{v:.0f}"
    else:
        mantissa, exponent = f"{v:.{sig - 1}e}".split("e")
        mantissa = mantissa.rstrip("0").rstrip(".")
        text = f"{mantissa}×10{str(int(exponent)).translate(_SUPERSCRIPT)}"
    return "0" if text in ("-0", "-0.0") else sign + text


ZERO_TOLERANCE: Final = 1e-9
"""Relative tolerance under which a displayed value is zero: a value whose magnitude is at most this
fraction of its quantity's scale (the largest value of that quantity shown beside it) is the round-off
of a sum that is zero (an average power of 3.79e-14 W beside a peak of 3993 W), and prints as 0. A double
carries about 16 digits and the cycle sums a few thousand samples, so the round-off stays below 1e-12
of the scale; a real value below 1e-9 of the scale is also invisible at the 4 significant digits shown."""

METRIC_SCALES: Final = {
    "average_power_W": "peak_power_W",
    "rms_torque_Nm": "peak_torque_Nm",
    "accel_torque_Nm": "peak_torque_Nm",
    "run_torque_Nm": "peak_torque_Nm",
    "decel_torque_Nm": "peak_torque_Nm",
    "holding_torque_Nm": "peak_torque_Nm",
    "mean_speed_rpm": "max_speed_rpm",
    "peak_torque_speed_rpm": "max_speed_rpm",
}
"""The scale of each demand figure (``SizingResult.metrics``) for :func:`snap_zero`: the peak of its quantity."""


def snap_zero(value: float | None, scale: float | None, rel: float = ZERO_TOLERANCE) -> float | None:
    """``value``, or 0.0 when ``|value| <= rel * |scale|`` (see ``ZERO_TOLERANCE``); None and non-finite
    values, and a zero or missing scale, leave it as it is."""
    if value is None or scale is None or not math.isfinite(value) or not math.isfinite(scale) or scale == 0.0:
        return value
    return 0.0 if abs(value) <= rel * abs(scale) else value


def snapped_metrics(metrics: Mapping[str, Any]) -> dict[str, Any]:
    """The demand figures with each one that is zero to within its scale (``METRIC_SCALES``) set to 0.0."""
    out = dict(metrics)
    for key, scale in METRIC_SCALES.items():
        if isinstance(out.get(key), (int, float)) and isinstance(metrics.get(scale), (int, float)):
            out[key] = snap_zero(float(out[key]), float(metrics[scale]))
    return out


def fmt_percent(margin: float | None) -> str:
    """A margin (available / required - 1) as a signed percentage; "—" when undefined."""
    if margin is None or math.isnan(margin) or math.isinf(margin):
        return "—"
    return f"{margin * 100:+.1f} %"


def _factor(quantity: str, unit: str) -> float:
    """Display value of 1 SI unit of ``quantity`` in ``unit`` (every display unit is offset-free)."""
    import pint

    from drivetrain.units import convert

    try:
        return convert(1.0, quantity, unit)
    except pint.errors.DimensionalityError:
        # Imperial habit: "oz*in*s^2" and "lb*in" mean ounce- and pound-force (as in units.parse).
        forced = _POUND_OUNCE.sub(lambda m: m.group(1) + "f", unit)
        return convert(1.0, quantity, forced)


@dataclass
class DisplayUnits:
    """The unit of every displayed quantity, with conversion from SI and formatting."""

    system: str
    units: dict[str, str]
    _factors: dict[str, float] = field(default_factory=dict, repr=False)

    def unit(self, quantity: str) -> str:
        """The pint unit string of ``quantity`` in this system."""
        return self.units.get(quantity, SI_UNITS.get(quantity, ""))

    def label(self, quantity: str) -> str:
        """The typographic unit label of ``quantity`` ("N·m")."""
        return pretty_unit(self.unit(quantity))

    def factor(self, quantity: str) -> float:
        """Display units per SI unit of ``quantity``."""
        if quantity not in self._factors:
            self._factors[quantity] = _factor(quantity, self.unit(quantity))
        return self._factors[quantity]

    def to(self, value: float, quantity: str) -> float:
        """An SI scalar in display units."""
        return float(value) * self.factor(quantity)

    def array(self, values: ArrayLike, quantity: str) -> NDArray[np.float64]:
        """SI values as a float array in display units."""
        return np.asarray(values, dtype=float) * self.factor(quantity)

    def num(self, value: float | None, quantity: str, sig: int = 4, signed: bool = False) -> str:
        """The number alone, converted and formatted."""
        return fmt_number(None if value is None else self.to(value, quantity), sig, signed)

    def fmt(self, value: float | None, quantity: str, sig: int = 4, signed: bool = False) -> str:
        """Converted value with its unit: ``1.027 N·m``."""
        label = self.label(quantity)
        return self.num(value, quantity, sig, signed) + (f" {label}" if label and label != "-" else "")

    def describe(self) -> str:
        """One line naming the system and its main units."""
        main = ", ".join(self.label(q) for q in ("torque", "angular_speed", "inertia", "length"))
        name = {"si": "SI", "imperial": "imperial", "as-given": "as given in the axis file"}.get(self.system,
                                                                                                  self.system)
        return f"{name} ({main})"


def display_units(choice: str, raw: Mapping[str, Any] | None = None) -> DisplayUnits:
    """The unit system for ``--units si|imperial|as-given``; ``raw`` is the axis file as written."""
    if choice == "si":
        return DisplayUnits("si", dict(SI_UNITS))
    if choice == "imperial":
        return DisplayUnits("imperial", dict(IMPERIAL_UNITS))
    if choice == "as-given":
        units = dict(SI_UNITS)
        units.update(units_in_file(raw or {}))
        return DisplayUnits("as-given", units)
    raise InputError("units", f"must be one of {', '.join(UNIT_CHOICES)}", choice)


def _leaves(node: Any, path: str = "") -> Iterator[tuple[str, str, Any]]:
    """(path, last key, value) of every scalar in a nested mapping/list, in file order."""
    if isinstance(node, Mapping):
        for k, v in node.items():
            key = str(k)
            sub = f"{path}.{key}" if path else key
            if isinstance(v, (Mapping, list, tuple)):
                yield from _leaves(v, sub)
            else:
                yield sub, key, v
    elif isinstance(node, (list, tuple)):
        for i, v in enumerate(node):
            sub = f"{path}[{i}]"
            if isinstance(v, (Mapping, list, tuple)):
                yield from _leaves(v, sub)
            else:
                yield sub, path.rsplit(".", 1)[-1], v


def leaves(raw: Mapping[str, Any]) -> list[tuple[str, Any]]:
    """Every scalar of the axis file with its dotted path (``mechanism.load.mass``, ``profile[0].move``)."""
    return [(p, v) for p, _, v in _leaves(raw)]


def unit_of(text: str) -> str | None:
    """The unit part of a quantity string ("10 mm" -> "mm"); None for a bare number or no number."""
    m = _NUMBER_UNIT.match(text)
    return m.group("unit") if m else None


def quantity_of(text: str, key: str = "") -> str | None:
    """What a quantity string measures (a name of ``drivetrain.units.QUANTITIES``), or None.

    Torque and energy share a dimension, so a torque is recognised only under a key naming a
    torque (``rated_torque``, ``friction_torque``, a rotary ``thrust``...); angles need an angle unit.
    """
    from drivetrain.units import parse

    unit = unit_of(text)
    if unit is None:
        return None
    probe = f"1 {unit}"
    order: tuple[str, ...] = _GUESS_ORDER
    if "torque" in key or key in ("thrust", "torque"):
        order = ("torque", *order)
    if "stiffness" in key or "damping" in key:
        order = ("linear_stiffness", "torsional_stiffness", "linear_damping", "torsional_damping", *order)
    for quantity in order:
        try:
            parse(probe, quantity, key)
        except (InputError, KeyError):
            continue
        if quantity == "angle" and not re.search(r"deg|rad|arcmin|arcsec|rev|turn|°", unit):
            continue
        return quantity
    return None


def units_in_file(raw: Mapping[str, Any]) -> dict[str, str]:
    """The first unit the axis file used for each displayed quantity (the profile first, for lengths)."""
    found: dict[str, str] = {}
    profile = raw.get("profile") if isinstance(raw, Mapping) else None
    ordered = list(_leaves({"profile": profile})) if profile is not None else []
    ordered += [leaf for leaf in _leaves(raw) if not leaf[0].startswith("profile")]
    for _, key, value in ordered:
        if not isinstance(value, str):
            continue
        quantity = quantity_of(value, key)
        unit = unit_of(value)
        if quantity is None or unit is None or quantity in found or quantity not in SI_UNITS:
            continue
        if quantity == "angular_speed" and key not in ("rated_speed", "max_speed", "speed"):
            continue
        found[quantity] = unit
    return found


# --------------------------------------------------------------------------- text metrics


@lru_cache(maxsize=2)
def _font(bold: bool) -> FT2Font:
    from matplotlib import font_manager, ft2font

    props = font_manager.FontProperties(family="DejaVu Sans", weight="bold" if bold else "normal")
    return ft2font.FT2Font(font_manager.findfont(props))


def text_width(text: str, size: float, bold: bool = False) -> float:
    """Width of ``text`` set in DejaVu Sans at ``size`` [pt], in points (the report's font)."""
    if not text:
        return 0.0
    font = _font(bold)
    font.set_size(size, 72)
    font.set_text(text, 0.0)
    return float(font.get_width_height()[0]) / 64.0


_GLUE = re.compile(r"(\d) (?=[%A-Za-zµ°Ω]\S{0,7}(\s|$))")


def wrap_text(text: str, width: float, size: float, bold: bool = False) -> list[str]:
    """Greedy word wrap of ``text`` to ``width`` [pt] at ``size`` [pt]; over-long words are split.

    A number is kept on the line of the short unit after it ("0.64 N·m", "+9.5 %").
    """
    glued = _GLUE.sub("\\1\u00a0", text)
    return [line.replace("\u00a0", " ") for line in _wrap_words(glued, width, size, bold)]


def _wrap_words(text: str, width: float, size: float, bold: bool) -> list[str]:
    lines: list[str] = []
    for para in text.split("\n"):
        current = ""
        for word in para.split(" "):
            candidate = f"{current} {word}" if current else word
            if text_width(candidate, size, bold) <= width:
                current = candidate
                continue
            if current:
                lines.append(current)
            while len(word) > 1 and text_width(word, size, bold) > width:
                k = len(word) - 1
                while k > 1 and text_width(word[:k], size, bold) > width:
                    k -= 1
                lines.append(word[:k])
                word = word[k:]
            current = word
        lines.append(current)
    return lines


def fit_text(text: str, size: float, width: float, bold: bool = False, smallest: float = 0.72) -> tuple[str, float]:
    """``text`` at the largest size <= ``size`` (down to ``smallest`` x size) that fits ``width``; clipped with
    an ellipsis beyond that. Units of ``size`` and ``width`` are the same (pt, or SVG user units)."""
    w = text_width(text, size, bold)
    if w <= width:
        return text, size
    scaled = size * width / w
    if scaled >= size * smallest:
        return text, scaled
    size *= smallest
    while len(text) > 1 and text_width(text + "…", size, bold) > width:
        text = text[:-1]
    return text.rstrip() + "…", size
