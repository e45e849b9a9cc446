r"""Friction on an inertia: Coulomb + viscous + Stribeck, with stiction.

Two forms of the Stribeck curve, chosen with ``method=``:

``"exponential"`` (default) -- the sliding torque

.. math:: T_f(\omega) = \mathrm{sign}(\omega)\,\big[T_C + (T_S - T_C)\, e^{-(|\omega|/\omega_S)^{\delta}}\big]
          + b\,\omega

(Armstrong-Helouvry, Dupont, Canudas de Wit, "A survey of models, analysis tools and compensation
methods for the control of machines with friction", Automatica 30(7), 1994, eq. (2), delta = 2 the
Gaussian form) with an *exact stick* state as Modelica's ``BearingFriction``
(Modelica.Mechanics.Rotational.Components.BearingFriction, after Otter, Elmqvist, Mattsson 1992):
at zero speed the element holds any torque up to the breakaway peak T_S and the speed stays
exactly 0; it breaks away when the other torques exceed T_S.

``"tanh"`` -- the smooth form of Simscape's Rotational Friction block (MathWorks documentation):

.. math:: T_f(\omega) = \sqrt{2e}\,(T_S - T_C)\, e^{-(\omega/\omega_{St})^2}\,\frac{\omega}{\omega_{St}}
          + T_C \tanh(\omega/\omega_{Coul}) + b\,\omega

with omega_St = omega_S sqrt(2) and omega_Coul = omega_S / 10 (the block's defaults relate the
thresholds the same way): continuous, no stick state, the peak T_S is reached at omega_St.

Torques [N m], speeds [rad/s], viscous coefficient [N m s/rad].
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from drivetrain.errors import InputError

FRICTION_METHODS: tuple[str, ...] = ("exponential", "tanh")
METHOD_CODE: dict[str, int] = {"exponential": 0, "tanh": 1}


@dataclass(frozen=True)
class Friction:
    """Friction acting between one inertia and the ground.

    Attributes (SI):
        coulomb: sliding (Coulomb) torque T_C [N m], >= 0.
        static: breakaway (static) torque T_S [N m], >= coulomb (defaults to coulomb).
        viscous: viscous coefficient b [N m s/rad], >= 0.
        stribeck_speed: characteristic Stribeck speed omega_S [rad/s], > 0.
        method: ``"exponential"`` (exact stick) or ``"tanh"`` (smooth).
        exponent: Stribeck exponent delta of the exponential form (2: Gaussian).
    """

    coulomb: float = 0.0
    static: float | None = None
    viscous: float = 0.0
    stribeck_speed: float = 0.01
    method: str = "exponential"
    exponent: float = 2.0

    def __post_init__(self) -> None:
        check_friction(self)

    @property
    def breakaway(self) -> float:
        """Breakaway torque [N m] (static, or Coulomb when no static value is given)."""
        return self.coulomb if self.static is None else self.static

    def torque(self, omega: ArrayLike) -> NDArray[np.float64]:
        """Sliding friction torque [N m] at speed omega [rad/s] (opposes motion when subtracted)."""
        if self.method == "tanh":
            return friction_torque_tanh(omega, self.coulomb, self.breakaway, self.viscous, self.stribeck_speed)
        return friction_torque_exponential(
            omega, self.coulomb, self.breakaway, self.viscous, self.stribeck_speed, self.exponent
        )


def check_friction(f: Friction, field: str = "friction") -> None:
    """Raise ``InputError`` naming ``field`` for inconsistent friction parameters."""
    for name in ("coulomb", "viscous"):
        v = getattr(f, name)
        if not math.isfinite(v) or v < 0.0:
            raise InputError(f"{field}.{name}", "must be a finite number >= 0", v)
    if f.static is not None and (not math.isfinite(f.static) or f.static < f.coulomb):
        raise InputError(f"{field}.static", f"must be >= the Coulomb torque {f.coulomb:g} N*m", f.static)
    if not math.isfinite(f.stribeck_speed) or f.stribeck_speed <= 0.0:
        raise InputError(f"{field}.stribeck_speed", "must be > 0 rad/s", f.stribeck_speed)
    if f.method not in FRICTION_METHODS:
        raise InputError(f"{field}.method", f"must be one of {', '.join(FRICTION_METHODS)}", f.method)
    if not math.isfinite(f.exponent) or f.exponent <= 0.0:
        raise InputError(f"{field}.exponent", "must be > 0", f.exponent)


def friction_torque_exponential(
    omega: ArrayLike,
    coulomb: float,
    static: float,
    viscous: float,
    stribeck_speed: float,
    exponent: float = 2.0,
) -> NDArray[np.float64]:
    r"""Sliding friction with the exponential Stribeck curve [N m].

    .. math:: T_f = \mathrm{sign}(\omega)[T_C + (T_S - T_C) e^{-(|\omega|/\omega_S)^\delta}] + b \omega

    omega [rad/s]; coulomb T_C, static T_S [N m]; viscous b [N m s/rad]; stribeck_speed
    omega_S [rad/s]. At omega = 0 it returns 0: the stuck torque is not a function of speed
    (it balances the other torques up to T_S; see ``simulate``).
    Source: Armstrong-Helouvry et al., Automatica 30(7), 1994; Modelica BearingFriction.

    >>> float(friction_torque_exponential(1e9, 1.0, 2.0, 0.0, 0.1))
    1.0
    """
    w = np.asarray(omega, dtype=float)
    s = np.exp(-((np.abs(w) / stribeck_speed) ** exponent))
    return np.asarray(np.sign(w) * (coulomb + (static - coulomb) * s) + viscous * w, dtype=float)


def friction_torque_tanh(
    omega: ArrayLike, coulomb: float, static: float, viscous: float, stribeck_speed: float
) -> NDArray[np.float64]:
    r"""Smooth Stribeck friction (Simscape Rotational Friction form) [N m].

    .. math:: T_f = \sqrt{2e}(T_S - T_C) e^{-(\omega/\omega_{St})^2}\frac{\omega}{\omega_{St}}
              + T_C \tanh(\omega/\omega_{Coul}) + b\omega,
              \quad \omega_{St} = \sqrt{2}\,\omega_S,\ \omega_{Coul} = \omega_S/10

    Source: MathWorks Simscape documentation, "Rotational Friction" block.

    >>> round(float(friction_torque_tanh(1e3, 1.0, 2.0, 0.0, 0.1)), 6)
    1.0
    """
    w = np.asarray(omega, dtype=float)
    w_st = math.sqrt(2.0) * stribeck_speed
    w_coul = stribeck_speed / 10.0
    x = w / w_st
    return np.asarray(
        math.sqrt(2.0 * math.e) * (static - coulomb) * np.exp(-(x**2)) * x
        + coulomb * np.tanh(w / w_coul)
        + viscous * w,
        dtype=float,
    )


def friction_from_spec(spec: Any, field: str) -> Friction:
    """Build a ``Friction`` from its axis-file form, e.g.
    ``{coulomb: 0.1 N*m, static: 0.15 N*m, viscous: 1e-4, stribeck_speed: 2 rad/s, method: tanh}``."""
    from drivetrain.units import parse

    if not isinstance(spec, dict):
        raise InputError(field, "must be a mapping of friction parameters", spec)
    allowed = {"coulomb", "static", "viscous", "stribeck_speed", "method", "exponent"}
    for key in spec:
        if key not in allowed:
            raise InputError(f"{field}.{key}", f"is not a friction parameter (allowed: {', '.join(sorted(allowed))})",
                             spec[key])
    kwargs: dict[str, Any] = {}
    if "coulomb" in spec:
        kwargs["coulomb"] = parse(spec["coulomb"], "torque", f"{field}.coulomb")
    if "static" in spec:
        kwargs["static"] = parse(spec["static"], "torque", f"{field}.static")
    if "viscous" in spec:
        kwargs["viscous"] = parse(spec["viscous"], "torsional_damping", f"{field}.viscous")
    if "stribeck_speed" in spec:
        kwargs["stribeck_speed"] = parse(spec["stribeck_speed"], "angular_speed", f"{field}.stribeck_speed")
    if "exponent" in spec:
        kwargs["exponent"] = parse(spec["exponent"], "dimensionless", f"{field}.exponent")
    if "method" in spec:
        kwargs["method"] = str(spec["method"])
    try:
        return Friction(**kwargs)
    except InputError as err:
        raise InputError(field + err.field.removeprefix("friction"), err.rule, err.value) from None
