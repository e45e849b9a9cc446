"""A screw without ``mechanism.screw`` is still bounded from its nominal diameter and length; a belt axis
without its stiffness says the modes take it rigid (docs/checks.md, "Screw limits without mechanism.screw")."""

from __future__ import annotations

import math
from typing import Any

import pytest

from drivetrain.axis.model import parse_axis
from drivetrain.duty.cycle import duty_cycle
from drivetrain.sizing.mechanism_checks import mechanism_checks, prepare_many, screw_bounds


def _screw(move: str = "400 mm", time: str = "0.3 s", **mech: Any) -> dict[str, Any]:
    return {"axis": "screw", "mechanism": {"type": "ball_screw", "lead": "10 mm", "diameter": "25 mm", "length": "1 m",
                                           "load": {"mass": "20 kg"}, **mech},
            "profile": [{"move": move, "time": time, "accel": "0.1 s"}, {"dwell": "0.5 s"}],
            "motor": {"rated_torque": "5 N*m", "peak_torque": "15 N*m", "rated_speed": "3000 rpm",
                      "max_speed": "6000 rpm", "inertia": "5 kg*cm^2"}}


def _checks(d: dict[str, Any]) -> dict[str, dict[str, Any]]:
    ax = parse_axis(d)
    return {c.name: c.to_dict() for c in mechanism_checks(ax, duty_cycle(ax))}


def test_the_bound_of_a_25_mm_1_m_screw_by_hand() -> None:
    """THK A15-32: N1 = 0.8 lambda^2 d1 / (4 l^2) sqrt(E / rho) with lambda = 3.927 (fixed-supported),
    d1 = 25 mm, l = 1 m, E = 206 GPa, rho = 7850 kg/m^3: 395.0 rad/s = 3772 rpm (THK's folded form
    15.1 d1 / l^2 x 10^7 = 3775 min^-1)."""
    _, _, crit, missing = screw_bounds(1.0, 0.025, 0.4)
    by_hand = 0.8 * 3.927**2 * 0.025 / 4.0 * math.sqrt(206e9 / 7850.0)
    assert missing == "" and crit == pytest.approx(by_hand, rel=1e-12)
    assert crit * 60 / (2 * math.pi) == pytest.approx(3775.0, rel=2e-3)


def test_a_screw_asked_beyond_even_its_bound_fails_with_the_reason() -> None:
    """400 mm in 0.3 s with 0.1 s ramps on a 10 mm lead: 2 m/s, 12,000 rpm, against at most 3772 rpm."""
    c = _checks(_screw())["screw_critical_speed"]
    assert c["status"] == "fail" and not c["ok"]
    assert c["required"] == pytest.approx(12000.0)
    assert c["available"] == pytest.approx(3772.0, abs=1.0) and c["margin"] < 0.0
    assert "whatever the root diameter" in c["note"] and "nominal 25 mm" in c["note"]


def test_within_the_bound_the_check_is_unknown_and_says_what_decides_it() -> None:
    """A slow move: 1,000 rpm is below the bound; only the root diameter decides it."""
    checks = _checks(_screw(move="50 mm", time="0.4 s"))
    for name in ("screw_critical_speed", "screw_buckling", "screw_tensile_compressive"):
        c = checks[name]
        assert c["status"] == "unknown" and c["margin"] is None and c["available"] is None and c["ok"]
        assert "mechanism.screw.root_diameter" in c["note"]


def test_without_a_length_the_speed_and_buckling_say_what_to_give() -> None:
    d = _screw(move="50 mm", time="0.4 s")
    del d["mechanism"]["length"]
    checks = _checks(d)
    assert checks["screw_critical_speed"]["status"] == "unknown"
    assert "mechanism.length" in checks["screw_critical_speed"]["note"]


def test_a_given_screw_block_is_judged_as_before() -> None:
    checks = _checks(_screw(screw={"root_diameter": "21 mm"}))
    assert "status" not in checks["screw_critical_speed"] and checks["screw_critical_speed"]["margin"] < 0.0


def test_many_axes_get_the_same_bounds() -> None:
    """prepare_many (a study's many axes) gives each axis what mechanism_checks gives it."""
    axes = [parse_axis(_screw(move=m)) for m in ("50 mm", "400 mm")]
    pairs = [(a, duty_cycle(a)) for a in axes]
    many = prepare_many(pairs)
    assert many == [mechanism_checks(a, d) for a, d in pairs]


def test_a_belt_without_its_stiffness_is_said_to_be_rigid_in_the_modes() -> None:
    belt = {"axis": "belt", "mechanism": {"type": "timing_belt", "diameter": "50 mm", "load": {"mass": "5 kg"}},
            "profile": [{"move": "500 mm", "time": "0.5 s"}, {"dwell": "0.2 s"}],
            "motor": {"rated_torque": "2 N*m", "peak_torque": "6 N*m", "rated_speed": "3000 rpm",
                      "max_speed": "6000 rpm", "inertia": "2 kg*cm^2"}}
    c = _checks(belt)["belt_stiffness"]
    assert c["status"] == "unknown" and "rigid" in c["note"] and "specific_stiffness" in c["note"]
    belt["mechanism"]["belt"] = {"specific_stiffness": "1e5 N", "centre_distance": "1 m"}
    assert "belt_stiffness" not in _checks(belt)
