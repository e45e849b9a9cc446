r"""Values a motor row implies: computed once, when the catalog table is built or a row imported.

Where a vendor table gives one of a pair and not the other, the other follows from it:

* stall torque :math:`T_0 = K_t I_0` and rated torque :math:`T_N = K_t I_N` (torque constant times the
  current of the same operating point, both rms);
* torque constant from a torque and its current, :math:`K_t = T_0 / I_0`, else :math:`T_N / I_N`
  (the vendor's own operating points, so the currents sizing computes as T / K_t are the vendor's);
* else torque constant from the back-EMF constant of a sinusoidal PMSM,
  :math:`K_t\,[\mathrm{N\,m/A_{rms}}] = \sqrt3\,K_{e,LL,rms}\,[\mathrm{V\,s/rad}]`, on the basis the row
  states (``back_emf_basis``: line-to-line or phase, rms or peak; :data:`KE_TO_LL_RMS`).
  Source: power balance :math:`T\omega = 3 E_{ph,rms} I` with
  :math:`E_{ph,rms} = K_{e,LL,rms}\,\omega/\sqrt3`; Novanta, "What Motor Torque Constant to Use for
  Drive Type - Theory and Application" (sinusoidal torque constant); MathWorks Motor Control Blockset
  ``mcb.getPMSMParameters`` (BLY171D: Ke = 3.8 V_pk,LL/krpm, psi = 0.0052 Wb, p = 4). Checked on
  Siemens 1FT7044-5AK7 (Configuration Manual PFT7S 01/2009, Table 4-8, p. 90): k_E = 57 V/krpm gives
  0.943 N m/A against the printed hot k_T = 0.88 (magnets weaken with heat; ``catalog check`` allows
  15 %). The printed pair is preferred because it is the hot value.

The back-EMF constant is not derived from K_t: a datasheet K_t is the hot value, a few per cent below
:math:`\sqrt3 K_e`, so a K_e from it would understate the back-EMF and overstate the voltage-limited speed.

Each computed field is added to the row's ``derived`` list and its formula to ``derivation``
(``voltage_class.add_derived``); ``catalog show``, the sizing JSON and the report show them.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Any

from drivetrain.catalog.voltage_class import add_derived

DERIVED_KT = "derived = rated torque / rated current of the same vendor table (not printed)"
"""How a derived torque constant is named in the answer (data/SOURCES.md, "Derived torque constants")."""


def _num(values: dict[str, Any], name: str) -> float | None:
    v = values.get(name)
    return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) and v > 0 else None


KE_TO_LL_RMS = {"ll_rms": 1.0, "ll_peak": 1.0 / math.sqrt(2.0), "phase_rms": math.sqrt(3.0),
                "phase_peak": math.sqrt(3.0) / math.sqrt(2.0)}
"""Factor from k_E on each basis to the line-to-line rms value: line-to-line = sqrt(3) x phase,
rms = peak / sqrt(2) for sinusoidal quantities (the same conversion as ``physics.motor_electrical.ke_si``,
which the catalog layer does not import)."""


def kt_from_back_emf(ke: float, basis: str) -> float:
    """Torque constant [N m/A rms] of a sinusoidal PMSM from k_E [V s/rad] on ``basis``:
    k_T = sqrt(3) k_E,LL,rms (module docstring for the source). ValueError for an unknown basis."""
    if basis not in KE_TO_LL_RMS:
        raise ValueError(f"back_emf_basis must be one of {', '.join(KE_TO_LL_RMS)}, got {basis!r}")
    return math.sqrt(3.0) * ke * KE_TO_LL_RMS[basis]


def _fmt(x: float, unit: str) -> str:
    return f"{x:.6g} {unit}"


def _torque_from_kt(values: dict[str, Any], torque: str, current: str, label: str) -> bool:
    kt, i = _num(values, "torque_constant"), _num(values, current)
    if _num(values, torque) is not None or kt is None or i is None:
        return False
    values[torque] = kt * i
    add_derived(values, torque, f"{torque} = torque_constant x {current} = {_fmt(kt, 'N*m/A')} x {_fmt(i, 'A')} "
                                f"({label})")
    return True


def _kt(values: dict[str, Any]) -> bool:
    if _num(values, "torque_constant") is not None:
        return False
    for torque, current in (("stall_torque", "stall_current"), ("rated_torque", "rated_current")):
        t, i = _num(values, torque), _num(values, current)
        if t is not None and i is not None and f"{torque}" not in str(values.get("derived") or "").split(","):
            values["torque_constant"] = t / i
            add_derived(values, "torque_constant",
                        f"torque_constant = {torque} / {current} = {_fmt(t, 'N*m')} / {_fmt(i, 'A')}")
            return True
    ke = _num(values, "back_emf")
    if ke is not None:
        basis = str(values.get("back_emf_basis") or "ll_rms")
        values["torque_constant"] = kt_from_back_emf(ke, basis)
        add_derived(values, "torque_constant",
                    f"torque_constant = sqrt(3) x k_E,LL,rms = {_fmt(values['torque_constant'], 'N*m/A')} from "
                    f"back_emf {_fmt(ke, 'V*s/rad')} ({basis}; sinusoidal PMSM, catalog.derive)")
        return True
    return False


_STEPS: tuple[Callable[[dict[str, Any]], bool], ...] = (
    _kt,
    lambda v: _torque_from_kt(v, "stall_torque", "stall_current", "stall point"),
    lambda v: _torque_from_kt(v, "rated_torque", "rated_current", "rated point"),
)


def complete_row(table: str, values: dict[str, Any]) -> None:
    """The values a row implies and its voltage class by its vendor's model-code rule
    (``voltage_class.apply``), each flagged derived with its formula: once, when the shipped table is
    built (``db.shipped_rows``) or a row imported or edited, never per sizing. ``table``: the table's name."""
    from drivetrain.catalog import voltage_class

    if table == "motor":
        derive_motor(values)
    if table in ("motor", "drive"):
        voltage_class.apply(values, table)


def derive_motor(values: dict[str, Any]) -> list[str]:
    """Fill the fields an AC servo row implies (module docstring); returns the names filled.

    ``values``: one motor row keyed by field name (SI). A given value is never replaced.
    """
    if values.get("kind") not in (None, "ac_servo"):
        return []
    filled: list[str] = []
    before = {k: values.get(k) for k in ("torque_constant", "stall_torque", "rated_torque")}
    for step in _STEPS:
        step(values)
    for name, old in before.items():
        if old is None and values.get(name) is not None and math.isfinite(float(values[name])):
            filled.append(name)
    return filled


def formulas(row: Mapping[str, Any]) -> dict[str, str]:
    """Each derived field of a row (a database row keyed by column, or a ``catalog.get`` record) with how it
    was computed: the formula stored when the table was built, else what the row's data file says
    (``rated_torque_basis``; a k_T derived in the electrical table, data/SOURCES.md)."""
    from drivetrain.catalog.voltage_class import SEPARATOR

    derived = row.get("derived") or []
    names = [n for n in (derived.split(",") if isinstance(derived, str) else derived) if n]
    stored: dict[str, str] = {}
    for text in str(row.get("derivation") or "").split(SEPARATOR):
        name, sep, _ = text.partition(" = ")
        if sep:
            stored[name] = text
    out: dict[str, str] = {}
    for name in names:
        if name in stored:
            out[name] = stored[name]
        elif name in ("rated_torque", "rated_speed") and row.get("rated_torque_basis") not in (None, "", "source"):
            out[name] = f"{name}: {row['rated_torque_basis']}"
        elif name == "torque_constant":

            out[name] = f"torque_constant: {DERIVED_KT}"
        else:
            out[name] = f"{name}: derived by the row's source, not read from a datasheet"
    return out
