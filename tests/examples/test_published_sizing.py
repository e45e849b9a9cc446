"""Published sizing examples through ``drivetrain size`` on axis files (tests/axes/).

Each test names its source and asserts the published numbers with the tolerance stated in
tests/data/published.json. Vendor examples use g = 9.8 and the ``load_torque_only`` model.
"""

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from drivetrain.physics.acceleration import fanuc_accel_torque, fanuc_speed_at_peak_torque
from drivetrain.physics.averages import cubic_mean
from drivetrain.sizing.pipeline import size

TESTS = Path(__file__).parents[1]
AXES = TESTS / "axes"
PUBLISHED = {e["id"]: e for e in json.loads((TESTS / "data" / "published.json").read_text())}


def published(example: str, key: str) -> tuple[float, float]:
    out = PUBLISHED[example]["outputs"][key]
    return out["published"], out["tol_rel"]


def cli_json(path: Path) -> dict:
    proc = subprocess.run([sys.executable, "-m", "drivetrain.cli", "size", str(path), "--json"],
                          capture_output=True, text=True, timeout=120, check=True)
    return json.loads(proc.stdout)


def test_yaskawa_sigma2_through_the_cli() -> None:
    ex = "yaskawa_sigma2_speed_500kg"
    out = cli_json(AXES / "yaskawa_sigma2_speed.yaml")
    for key, value in (("t_cycle", out["cycle_time_s"]), ("N", out["max_speed_rpm"]),
                       ("TL", out["run_torque_Nm"]), ("JL", out["load_inertia_kgm2"])):
        pub, tol = published(ex, key)
        assert value == pytest.approx(pub, rel=tol), key
    accel = next(s for s in out["segments"] if s["kind"] == "accel")
    run = next(s for s in out["segments"] if s["kind"] == "run")
    assert accel["t1_s"] - accel["t0_s"] == pytest.approx(published(ex, "ta")[0], rel=1e-9)
    assert run["t1_s"] - run["t0_s"] == pytest.approx(published(ex, "tc")[0], rel=1e-9)


def test_yaskawa_sigma5_geared_through_size() -> None:
    ex = "yaskawa_sigma5_geared_250kg"
    out = size(AXES / "yaskawa_sigma5_geared.yaml").to_dict()
    for key, value in (("nM", out["max_speed_rpm"]), ("TL", out["run_torque_Nm"]), ("JL", out["load_inertia_kgm2"]),
                       ("PO", out["operation_power_W"]), ("t_cycle", out["cycle_time_s"])):
        pub, tol = published(ex, key)
        assert value == pytest.approx(pub, rel=tol), key


def test_yaskawa_sigma5_four_quadrant_differs_only_in_the_ramps() -> None:
    """The four-quadrant model also loses efficiency on the inertial torque of the screw and load."""
    lto = size(AXES / "yaskawa_sigma5_geared.yaml").to_dict()
    text = (AXES / "yaskawa_sigma5_geared.yaml").read_text().replace("load_torque_only", "four_quadrant")
    from drivetrain.axis.model import parse_axis
    from drivetrain.axis.yaml_text import parse_yaml

    axis = parse_axis(parse_yaml(text))
    fq = size(axis).to_dict()
    assert fq["run_torque_Nm"] == pytest.approx(lto["run_torque_Nm"], rel=1e-12)
    # Hand formulas (ServoSoft quadrants): accel motoring, decel braking through the screw.
    r, eta = 2.0, 0.9
    j_gear, j_screw = 0.4e-4, axis.mechanism.stage.inertia_in / r**2
    j_load = axis.mechanism.stage.inertia_inside / r**2
    alpha = 15 / 60 / 0.01 * r * 2 * math.pi / 0.1
    t_ext = 9.8 * 0.2 * 250 * 0.01 / (2 * math.pi * r)
    assert fq["accel_torque_Nm"] == pytest.approx((j_gear + j_screw) * alpha + (j_load * alpha + t_ext) / eta,
                                                  rel=1e-9)
    assert fq["decel_torque_Nm"] == pytest.approx(-(j_gear + j_screw) * alpha + (-j_load * alpha + t_ext) * eta,
                                                  rel=1e-9)
    assert lto["decel_torque_Nm"] == pytest.approx(-(j_gear + j_screw + j_load) * alpha + t_ext / eta, rel=1e-9)


def test_yaskawa_sigma_s_30w_powers_and_peak_torque() -> None:
    """Yaskawa Sigma-S 2.4.1: P_o = 11.0 W, P_a = 46.78 W, T_P = 0.186 N m.

    The source says J_L <= allowable (30 x J_M = 0.189e-4) is satisfied, but its own J_L =
    0.474e-4 is 2.5 times that (flagged in published.json): a correct tool reports the failure.
    """
    ex = "yaskawa_es_30W_provisional"
    res = size(AXES / "yaskawa_es_30w.yaml")
    out = res.to_dict()
    pub, tol = published(ex, "PO")
    assert out["operation_power_W"] == pytest.approx(pub, rel=tol)
    pub, tol = published(ex, "Pa")
    assert out["acceleration_power_W"] == pytest.approx(pub, rel=tol)
    pub, tol = published(ex, "TP")
    assert out["motor"]["accel_torque_Nm"] == pytest.approx(pub, rel=tol)
    ratio_check = {c["name"]: c for c in out["motor"]["checks"]}["inertia_ratio"]
    assert ratio_check["available"] * 0.00629e-4 == pytest.approx(published(ex, "allowable_load_inertia")[0],
                                                                   rel=0.01)
    assert not ratio_check["ok"]


def test_harmonic_actuator_peak_torque() -> None:
    """harmonicreducer.com '7 steps': 3000 rpm / 101 in 0.12 s: alpha = 25.9 rad/s^2, T = 22.8 N m."""
    ex = "harmonic_actuator_peak_torque"
    res = size(AXES / "harmonic_actuator.yaml")
    alpha_out = float(np.max(np.abs(res.duty.samples.a)))
    pub, tol = published(ex, "alpha_out")
    assert alpha_out == pytest.approx(pub, rel=tol)
    gearbox_out = float(np.max(np.abs(res.duty.stage_torque[0])))
    pub, tol = published(ex, "T_peak")
    assert gearbox_out == pytest.approx(pub, rel=tol)


def test_harmonic_average_load_torque() -> None:
    """honpine.com strain-wave selection: T_av = (sum n t |T|^3 / sum n t)^(1/3) = 89 N m."""
    ex = "harmonic_average_load_torque"
    segs = np.array(PUBLISHED[ex]["inputs"]["segments_T_Nm_t_s_n_rpm"] + [PUBLISHED[ex]["inputs"]["stop_segment"]])
    t_av = cubic_mean(segs[:, 0], segs[:, 2], segs[:, 1])
    pub, tol = published(ex, "Tav")
    assert t_av == pytest.approx(pub, rel=tol)


def test_fanuc_accel_torque_under_position_loop() -> None:
    """FANUC B-65262EN/03 3.2.4.1: T_a = 74.9 N m, V_r = 2050 rpm.

    The source states t_a = 0.1 s and uses it for V_r, but substitutes 0.08 s in the printed T_a
    line (flagged in published.json); with 0.1 s, T_a = 62.7 N m. Both are asserted.
    """
    ex = "fanuc_alphai_accel_torque"
    w = 3000 * 2 * math.pi / 60
    t_a = fanuc_accel_torque(w, 0.08, 30.0, 0.0053, 0.01412, 0.9)
    pub, tol = published(ex, "Ta")
    assert t_a == pytest.approx(pub, rel=tol)
    pub, tol = published(ex, "Ta_kgf_cm")
    assert t_a / 9.8 * 100 == pytest.approx(pub, rel=tol)
    assert fanuc_accel_torque(w, 0.1, 30.0, 0.0053, 0.01412, 0.9) == pytest.approx(62.6557, rel=1e-4)
    pub, tol = published(ex, "Vr")
    assert fanuc_speed_at_peak_torque(3000, 0.1, 30.0) == pytest.approx(pub, rel=tol)
