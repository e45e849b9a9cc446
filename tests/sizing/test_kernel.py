"""The selection checks (sizing/kernel.py, whole-array numpy) equal, to the bit, the per-candidate loop
they were first written as (below, run by the interpreter: plain IEEE 754 double arithmetic, no fused
multiply-add), on sampled motors of the shipped catalog against every gearbox row and direct drive of
several example axes: every margin, required and available value, the worst margin and the bits of the
failing and unknown checks. The peak-torque bin search, the closest failures and a ``drivetrain size``
process without numba are checked too."""

import json
import math
import os
import subprocess
import sys
import textwrap
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray

from drivetrain import catalog
from drivetrain.axis.model import Margins, load_axis
from drivetrain.duty.cycle import duty_cycle
from drivetrain.sizing import selection
from drivetrain.sizing.kernel import (
    BRAKE,
    D_INERTIA,
    D_PEAK,
    D_RMS,
    FIT,
    FIT_TOLERANCE,
    GB_AXIAL,
    GB_ESTOP,
    GB_MEAN_SPEED,
    GB_PEAK,
    GB_RADIAL,
    GB_RATED,
    GB_SPEED,
    INERTIA,
    N_CHECKS,
    N_DETAIL,
    PEAK,
    RMS,
    SPEED,
    check,
    closest_failing,
)

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ("ball_screw", "belt", "hoist", "rack_pinion", "rotary")
_RPM = 60.0 / (2.0 * np.pi)
_MM = 1e3


def _eq(motor: float, adapter: float) -> float:
    """A motor dimension against the adapter's: +inf within FIT_TOLERANCE, NaN where either is unknown."""
    if math.isnan(motor) or math.isnan(adapter):
        return math.nan
    return math.inf if abs(motor - adapter) <= FIT_TOLERANCE else -abs(motor / adapter - 1.0)


def _comb(*xs: float) -> float:
    """The smallest known shortfall, else NaN where any is unknown, else the smallest."""
    lo, gap = math.inf, False
    for x in xs:
        if math.isnan(x):
            gap = True
        elif x < lo:
            lo = x
    return lo if (lo < 0.0 or not gap) else math.nan


def loop_check(model: tuple[Any, ...], row_start: NDArray[np.int64], rows: NDArray[np.int64],
          pick: NDArray[np.int64], motor: NDArray[np.int32], slot: NDArray[np.int32],
          worst: NDArray[np.float64], failed: NDArray[np.uint16], unknown: NDArray[np.uint16],
          detail: NDArray[np.float64]) -> None:
    """The selection checks as first written: one candidate at a time, in plain Python floats."""
    (j_rotor, t_peak, w_max, m_shaft, m_flange, m_pilot, m_bolt, m_brake, cont_mean, full_row, env_full, g_ratio,
     g_eff, hull_speed, hull_t, hull_a, all_t, all_a, sums, g_speed, g_j_load, gb_j, gb_nmax, gb_nmean, gb_t2n, gb_t2b,
     gb_t2not, gb_bore_max, gb_bore_min, gb_flange, gb_pilot, gb_adapters, gb_f2r, gb_f2a, par) = model
    period, tm, rm, sm, limit, out_cubic, run_t = par[0], par[1], par[2], par[3], par[4], par[5], par[6]
    out_peak, fs, hold, load_r, load_a = par[7], par[8], par[9], par[10], par[11]
    n_motors, n_bins, n_v, n_all = j_rotor.shape[0], hull_speed.shape[1], hull_t.shape[2], all_t.shape[1]
    top = n_bins - 1
    listed = pick.shape[1] > 0
    n_pairs = pick.shape[1] if listed else (row_start.shape[0] - 1) * n_motors
    width = 1 if listed else int(np.max(np.diff(row_start)))
    # per row of the current group, and per row of the current pair
    r_direct = np.empty(width, dtype=np.bool_)
    r_j, r_speed, r_mean, r_t2n, r_t2b, r_t2not = (np.empty(width), np.empty(width), np.empty(width),
                                                   np.empty(width), np.empty(width), np.empty(width))
    r_bmax, r_bmin, r_fl, r_pi = np.empty(width), np.empty(width), np.empty(width), np.empty(width)
    r_row = np.empty(width, dtype=np.int64)
    # the margins that depend on the row alone
    r_mar_speed, r_mar_mean, r_mar_t2n, r_mar_t2b = np.empty(width), np.empty(width), np.empty(width), np.empty(width)
    j, peak_all, s = np.empty(width), np.empty(width), np.empty(width)
    req_p, av_p, mar_p = np.empty(width), np.empty(width), np.empty(width)
    mar = np.empty(N_CHECKS)
    req_t2b = out_peak * tm * (1.0 if math.isnan(fs) else fs)
    req_t2n = out_cubic * tm
    k = 0
    g_loaded = -1
    for pair in range(n_pairs):
        if listed:
            m, g, q0, q1 = pick[0, pair], pick[1, pair], pick[2, pair], pick[2, pair] + 1
        else:
            g, m = pair // n_motors, pair % n_motors
            q0, q1 = row_start[g], row_start[g + 1]
        n = q1 - q0
        req_s = g_speed[g, 0] * sm
        req_mean = g_speed[g, 1]
        if listed or g != g_loaded:
            for q in range(n):
                r = rows[q0 + q]
                r_row[q] = r
                d = r < 0
                r_direct[q] = d
                r_j[q] = 0.0 if d else gb_j[r]
                r_speed[q] = math.inf if d else gb_nmax[r]
                r_mean[q] = math.inf if d else gb_nmean[r]
                r_t2n[q] = math.inf if d else gb_t2n[r]
                r_t2b[q] = math.inf if d else gb_t2b[r]
                r_t2not[q] = math.inf if d else gb_t2not[r]
                r_bmax[q] = math.inf if d else gb_bore_max[r]
                r_bmin[q] = math.nan if d else gb_bore_min[r]
                r_fl[q] = math.nan if d else gb_flange[r]
                r_pi[q] = math.nan if d else gb_pilot[r]
                r_mar_speed[q] = r_speed[q] / req_s - 1.0 if req_s > 0.0 else math.inf
                r_mar_mean[q] = r_mean[q] / req_mean - 1.0 if req_mean > 0.0 else math.inf
                r_mar_t2n[q] = r_t2n[q] / req_t2n - 1.0 if req_t2n > 0.0 else math.inf
                r_mar_t2b[q] = r_t2b[q] / req_t2b - 1.0 if req_t2b > 0.0 else math.inf
                # an unknown rating leaves its check unknown, whatever is required
                r_mar_speed[q] = math.nan if math.isnan(r_speed[q]) else r_mar_speed[q]
                r_mar_mean[q] = math.nan if math.isnan(r_mean[q]) else r_mar_mean[q]
                r_mar_t2n[q] = math.nan if math.isnan(r_t2n[q]) else r_mar_t2n[q]
                if math.isnan(r_t2b[q]) or (not d and math.isnan(fs)):
                    r_mar_t2b[q] = math.nan  # or the cycle rate needs a shock factor that is not given
            g_loaded = g
        i = g_ratio[g]
        j_m = j_rotor[m]
        for q in range(n):
            j[q] = j_m + r_j[q]
        # peak motor torque over the cycle: the support function of the cycle's hull
        for q in range(n):
            peak_all[q] = abs(all_t[g, 0] + j[q] * all_a[g, 0])
        for v in range(1, n_all):
            for q in range(n):
                peak_all[q] = max(peak_all[q], abs(all_t[g, v] + j[q] * all_a[g, v]))
        # peak torque against the intermittent envelope
        slow = w_max[m] < hull_speed[g, top]
        if slow:
            # slower than the cycle's top speed: not judged on torque (max_speed fails instead)
            for q in range(n):
                s[q] = abs(hull_t[g, top, 0] + j[q] * hull_a[g, top, 0])
            for v in range(1, n_v):
                for q in range(n):
                    s[q] = max(s[q], abs(hull_t[g, top, v] + j[q] * hull_a[g, top, v]))
            for q in range(n):
                req_p[q], av_p[q], mar_p[q] = s[q] * tm, math.nan, math.nan
        else:
            # Worst bin, the first on ties and a NaN margin the worst (numpy's argmin over the
            # bins). From the top speed down (where the envelope is usually lowest) with "<=", so
            # the lowest index wins a tie; a bin is skipped when even the whole cycle's peak
            # torque there could not lower the margin (a bound: env_b / (peak tm) - 1 > margin).
            row = full_row[g, m]
            for q in range(n):
                bound = peak_all[q] * tm * (1.0 + 1e-12)
                rq, aq, mq = 0.0, 0.0, math.inf
                for b in range(top, -1, -1):
                    eb = env_full[row, b]
                    if math.isnan(mq):
                        if not math.isnan(eb):
                            continue  # only a NaN margin at a lower bin can replace a NaN one
                    elif b != top and eb > (mq + 1.0) * bound:
                        continue
                    sb = abs(hull_t[g, b, 0] + j[q] * hull_a[g, b, 0])
                    for v in range(1, n_v):
                        sb = max(sb, abs(hull_t[g, b, v] + j[q] * hull_a[g, b, v]))
                    rb = sb * tm
                    mb = eb / rb - 1.0 if rb > 0.0 else math.inf
                    if b == top or mb <= mq or math.isnan(mb):
                        rq, aq, mq = rb, eb, mb
                req_p[q], av_p[q], mar_p[q] = rq, aq, mq
        # the other checks, each a closed form in J
        s_tt, s_ta, s_aa = sums[g, 0], sums[g, 1], sums[g, 2]
        cont, w_m, j_l, t_pk = cont_mean[m, g], w_max[m], g_j_load[g], t_peak[m]
        sh, fl_m, pi_m, bc_m = m_shaft[m], m_flange[m], m_pilot[m], m_bolt[m]
        mar_motor_speed = w_m / req_s - 1.0 if req_s > 0.0 else math.inf
        t_l = run_t / i
        for q in range(n):
            jq = j[q]
            direct = r_direct[q]
            # RMS torque against the continuous torque at the mean speed
            rms = math.sqrt(max(s_tt + 2.0 * jq * s_ta + jq * jq * s_aa, 0.0) / period)
            req_r = rms * rm
            mar_r = cont / req_r - 1.0 if req_r > 0.0 else math.inf
            # inertia ratio, the gearbox's input inertia on the load side
            ir = (j_l + r_j[q]) / j_m
            mar_i = limit / ir - 1.0 if ir > 0.0 else math.inf
            # mechanical fit (checks.mechanical_fit): known shortfalls first, then unknowns
            mar_f = math.inf
            if not direct:
                m1 = r_bmax[q] / sh - 1.0
                m2 = sh / r_bmin[q] - 1.0 if not math.isnan(r_bmin[q]) else math.inf
                if math.isnan(sh):
                    m2 = math.nan
                # the flange onto one of the drawn adapters, else onto the named adapter (unknown: not named)
                ad = gb_adapters[r_row[q]].reshape(-1, 3)
                drawn = [a for a in range(len(ad)) if not math.isnan(ad[a, 1])]
                if drawn:
                    each = [_comb(ad[a, 0] / sh - 1.0 if not math.isnan(ad[a, 0]) else math.nan, _eq(pi_m, ad[a, 1]),
                                  _eq(bc_m, ad[a, 2])) for a in drawn]
                    known = [e for e in each if not math.isnan(e)]
                    best = max(known) if known else -math.inf
                    m3 = best if best >= 0.0 else (math.nan if len(known) < len(each) else best)
                else:
                    pilot_m = math.inf if math.isnan(r_pi[q]) else _eq(pi_m, r_pi[q])
                    if math.isnan(r_fl[q]):
                        m3 = pilot_m if pilot_m < 0.0 else math.nan
                    else:
                        m3 = _comb(_eq(fl_m, r_fl[q]), pilot_m)
                mar_f = _comb(m1, m2, m3)
            # gearbox: what passes at the motor's peak against the emergency-stop torque
            req_ge = 0.0 if direct else ((1.0 - jq / (jq + j_l)) * (t_pk - t_l) + t_l) * i * g_eff[g]
            mar_ge = math.inf if direct else (r_t2not[q] / req_ge - 1.0 if req_ge > 0.0 else math.inf)
            if math.isnan(r_t2not[q]):
                mar_ge = math.nan
            mar[PEAK], mar[RMS], mar[SPEED], mar[INERTIA], mar[FIT] = mar_p[q], mar_r, mar_motor_speed, mar_i, mar_f
            mar[GB_PEAK], mar[GB_RATED], mar[GB_ESTOP] = r_mar_t2b[q], r_mar_t2n[q], mar_ge
            mar[GB_SPEED], mar[GB_MEAN_SPEED] = r_mar_speed[q], r_mar_mean[q]
            # motor brake: only where the axis needs one (hold not NaN)
            req_b, av_b, mar_b = 0.0, math.inf, math.inf
            if not math.isnan(hold):
                req_b, av_b = hold / i * g_eff[g], m_brake[m]
                mar_b = math.nan if math.isnan(av_b) else (av_b / req_b - 1.0 if req_b > 0.0 else math.inf)
            mar[BRAKE] = mar_b
            # output loads against F2r / F2a (the row's)
            f2r = math.inf if direct else gb_f2r[r_row[q]]
            f2a = math.inf if direct else gb_f2a[r_row[q]]
            mar[GB_RADIAL] = math.inf if direct or load_r == 0.0 else (
                math.nan if math.isnan(f2r) else f2r / load_r - 1.0)
            mar[GB_AXIAL] = math.inf if direct or load_a == 0.0 else (
                math.nan if math.isnan(f2a) else f2a / load_a - 1.0)
            if listed:
                detail[PEAK, k], detail[RMS, k], detail[SPEED, k] = req_p[q], req_r, req_s * _RPM
                detail[INERTIA, k], detail[FIT, k] = ir, (0.0 if direct else sh * _MM)
                detail[GB_PEAK, k], detail[GB_RATED, k], detail[GB_ESTOP, k] = req_t2b, req_t2n, req_ge
                detail[GB_SPEED, k], detail[GB_MEAN_SPEED, k] = req_s * _RPM, req_mean * _RPM
                detail[BRAKE, k], detail[N_CHECKS + BRAKE, k] = req_b, av_b
                detail[GB_RADIAL, k], detail[N_CHECKS + GB_RADIAL, k] = (0.0 if direct else load_r), f2r
                detail[GB_AXIAL, k], detail[N_CHECKS + GB_AXIAL, k] = (0.0 if direct else load_a), f2a
                a = N_CHECKS
                detail[a + PEAK, k], detail[a + RMS, k], detail[a + SPEED, k] = av_p[q], cont, w_m * _RPM
                detail[a + INERTIA, k], detail[a + FIT, k] = limit, r_bmax[q] * _MM
                detail[a + GB_PEAK, k], detail[a + GB_RATED, k] = r_t2b[q], r_t2n[q]
                detail[a + GB_ESTOP, k] = r_t2not[q]
                detail[a + GB_SPEED, k], detail[a + GB_MEAN_SPEED, k] = r_speed[q] * _RPM, r_mean[q] * _RPM
                for c in range(N_CHECKS):
                    detail[2 * N_CHECKS + c, k] = mar[c]
                detail[D_RMS, k], detail[D_PEAK, k], detail[D_INERTIA, k] = rms, peak_all[q], ir
            else:
                # worst known margin (NaN if none is known), the bits of the checks that fail and
                # of those that cannot be judged
                w = math.nan
                bits, gaps = 0, 0
                for c in range(N_CHECKS):
                    x = mar[c]
                    if math.isnan(x):
                        if not (c == PEAK and slow):  # not judged, not unknown: max_speed fails instead
                            gaps |= 1 << c
                    else:
                        if x < 0.0:
                            bits |= 1 << c
                        if not x >= w:
                            w = x
                motor[k], slot[k], worst[k], failed[k], unknown[k] = m, q0 + q, w, bits, gaps
            k += 1



def _sub_model(model: tuple[Any, ...], motors: NDArray[np.intp]) -> tuple[Any, ...]:
    """The model of the selection restricted to some motors (every group, gearbox row and envelope row)."""
    out = [a[motors] for a in model[:8]]
    return (*out, model[8][motors], model[9][:, motors], *model[10:])


def _motors_to_check(model: tuple[Any, ...], rng: np.random.Generator) -> NDArray[np.intp]:
    """Motors of every kind the checks tell apart: fast enough for the top bin of some group (with and
    without an unknown envelope there), too slow for every group, and a random few."""
    full_row, env_full = model[9], model[10]
    reach = np.flatnonzero((full_row >= 0).any(axis=0))
    gap_rows = np.flatnonzero(np.isnan(env_full).any(axis=1))
    with_gap = np.unique(np.nonzero(np.isin(full_row, gap_rows))[1])
    slow = np.flatnonzero(~(full_row >= 0).any(axis=0))
    picks = [rng.choice(a, min(3, len(a)), replace=False) for a in (reach, with_gap, slow) if len(a)]
    picks.append(rng.choice(len(model[0]), 3, replace=False))
    return np.unique(np.concatenate(picks))


def _same_bits(a: NDArray[Any], b: NDArray[Any]) -> bool:
    """Equal values, NaN where NaN, and the same sign of every zero."""
    if a.dtype.kind != "f":
        return bool(np.array_equal(a, b))
    return bool(np.array_equal(a, b, equal_nan=True) and np.array_equal(np.signbit(a) | np.isnan(a),
                                                                        np.signbit(b) | np.isnan(b)))


@pytest.fixture(scope="module")
def whole_catalog() -> tuple[Any, Any]:
    return catalog.motors(), catalog.gearboxes()  # every motor and every gearbox kind


@pytest.mark.parametrize("name", EXAMPLES)
def test_the_arrays_equal_the_loop_to_the_bit(name: str, whole_catalog: tuple[Any, Any]) -> None:
    """Sampled motors of the whole shipped catalog against every gearbox row and direct drive of the axis."""
    motors, gb = whole_catalog
    axis = load_axis(ROOT / "examples" / f"{name}.yaml")
    c = selection.evaluate(axis, duty_cycle(axis), motors, gb, Margins())
    model = _sub_model(c.model, _motors_to_check(c.model, np.random.default_rng(sum(map(ord, name)))))
    rows = c.slot_row
    row_start = np.concatenate([[0], np.cumsum(np.bincount(c.slot_group, minlength=len(c.group_ratio)))])
    n = len(model[0]) * len(rows)
    grids = []
    for fn in (check, loop_check):
        out = (np.empty(n, dtype=np.int32), np.empty(n, dtype=np.int32), np.empty(n), np.empty(n, dtype=np.uint16),
               np.empty(n, dtype=np.uint16))
        with np.errstate(all="ignore"):
            fn(model, row_start, rows, np.empty((3, 0), dtype=np.int64), *out, np.empty((0, 0)))
        grids.append(out)
    assert all(_same_bits(a, b) for a, b in zip(*grids, strict=True))
    assert np.count_nonzero(grids[0][3]) and np.count_nonzero(grids[0][3] == 0)  # some fail, some pass
    # every candidate in detail
    group = np.repeat(np.arange(len(c.group_ratio)), np.diff(row_start))
    pick = np.stack([grids[0][0], group[grids[0][1]], grids[0][1]]).astype(np.int64)
    details = []
    for fn in (check, loop_check):
        out = np.empty((N_DETAIL, n))
        none = np.empty(0, dtype=np.int32)
        bits = np.empty(0, dtype=np.uint16)
        with np.errstate(all="ignore"):
            fn(model, np.zeros(1, dtype=np.int64), rows, pick, none, none, np.empty(0), bits, bits, out)
        details.append(out)
    assert _same_bits(details[0], details[1])


@settings(max_examples=300, deadline=None)
@given(st.integers(1, 6), st.integers(1, 4), st.integers(0, 2**32 - 1))
def test_the_worst_bin_search_equals_numpys_argmin_over_every_bin(n_bins: int, n_v: int, seed: int) -> None:
    """Ties, zero torque, unknown (NaN) and infinite envelopes: the bounded search over the bins gives the
    required, available and margin of the full scan's worst bin (the first on ties, a NaN margin first)."""
    from drivetrain.sizing.kernel import _support, _worst_bin

    rng = np.random.default_rng(seed)
    n_pairs, n = 4, 12
    hull_t = rng.choice([0.0, 1.0, -1.0, 2.0, 0.5], (1, n_bins, n_v))
    hull_a = rng.choice([0.0, 1.0, -2.0, 4.0], (1, n_bins, n_v))
    env = rng.choice([0.0, 1.0, 2.0, 3.0, np.inf, np.nan], (n_pairs, n_bins), p=[0.1, 0.3, 0.3, 0.1, 0.1, 0.1])
    pair = rng.integers(0, n_pairs, n)
    g = np.zeros(n, dtype=np.int64)
    j = rng.choice([0.0, 0.5, 1.0, 2.0], n)
    tm = 1.5
    # the whole cycle's hull holds every bin's vertices: its support bounds theirs
    peak_all = np.max(np.abs(hull_t.reshape(1, -1) + j[:, None] * hull_a.reshape(1, -1)), axis=1)
    with np.errstate(all="ignore"):
        got = _worst_bin(env, hull_t, hull_a, pair, g, j, peak_all, tm)
    rb = _support(hull_t[g], hull_a[g], j[:, None]) * tm
    eb = env[pair]
    with np.errstate(all="ignore"):
        mb = np.where(rb > 0.0, eb / rb - 1.0, np.inf)
    b = np.argmin(mb, axis=1)[:, None]
    want = [np.take_along_axis(x, b, axis=1)[:, 0] for x in (rb, eb, mb)]
    for a, w in zip(got, want, strict=True):
        assert _same_bits(a, w)


def test_no_closest_failing_when_none_is_asked_for() -> None:
    assert closest_failing(np.array([-1.0, 0.5]), np.array([1, 0], dtype=np.uint8), 0).tolist() == []
    assert closest_failing(np.array([-1.0, np.nan, -0.5]), np.array([1, 1, 1], dtype=np.uint8), 5).tolist() == [2, 0, 1]


@given(st.lists(st.sampled_from([-0.5, -0.25, -0.2, -0.1, 0.0, 0.3, -np.inf, np.nan]), min_size=1, max_size=3000),
       st.integers(1, 60), st.integers(0, 2**32 - 1))
@settings(max_examples=200, deadline=None)
def test_closest_failing_is_the_stable_sort_with_many_ties(worst: list[float], n: int, seed: int) -> None:
    """The block bound and the ties at the n-th key give the first n of a stable sort of every failure."""
    w = np.array(worst)
    failed = np.random.default_rng(seed).integers(0, 2, len(w)).astype(np.uint16)
    failing = np.flatnonzero(failed)
    key = np.where(np.isnan(w[failing]), -np.inf, w[failing])
    want = failing[np.argsort(-key, kind="stable")][:n]
    assert closest_failing(w, failed, n).tolist() == want.tolist()


OWN_PROCESS = textwrap.dedent("""
    import json, sys
    from drivetrain.cli import main
    sys.argv = ["drivetrain", "size", sys.argv[1], "--json"]
    code = main()
    from pydantic.plugin._loader import get_plugins
    import gc, os
    threads = len(os.listdir("/proc/self/task")) if os.path.isdir("/proc/self/task") else None
    print(json.dumps({"code": code, "plugins": list(get_plugins()), "threads": threads,
                      "collector": [gc.isenabled(), gc.get_freeze_count()], "modules": sorted(
        m for m in sys.modules if m in ("importlib.metadata", "email", "numpy.ma", "numba", "yaml"))}))
""")


@pytest.fixture
def fresh_env(tmp_path: Path) -> dict[str, str]:
    return {**os.environ, "DRIVETRAIN_CACHE_DIR": str(tmp_path / "cache"),
            "DRIVETRAIN_DATA_DIR": str(tmp_path / "data"), "PYTHONPATH": str(ROOT / "src")}


def test_a_drivetrain_process_loads_no_numba_plugin_machinery_or_masked_arrays(fresh_env: dict[str, str]) -> None:
    """A ``drivetrain size`` process, the first in empty cache folders and the next: numba is not imported
    (the checks are numpy), nor pydantic's plugin loader (importlib.metadata, email) with discovery off,
    nor numpy.ma (by np.unique), nor the YAML library for a file read before (axis/yaml_cache.py); numpy's
    OpenBLAS starts no thread; the garbage collector is on, the start-up imports' objects frozen
    (cli._import_for_sizing); the answer is main(argv)'s in a program whose pydantic looks for plugins,
    whose OpenBLAS runs its threads and whose collector ran throughout."""
    env = {k: v for k, v in fresh_env.items()
           if k not in ("PYDANTIC_DISABLE_PLUGINS", "OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS")}
    axis = str(ROOT / "examples" / "ball_screw.yaml")
    runs = []
    for _ in range(2):  # the first run remembers the unit factors and the file's data
        runs.append(subprocess.run([sys.executable, "-c", OWN_PROCESS, axis], env=env, capture_output=True, text=True,
                                   check=True).stdout)
    first = json.loads(runs[0].splitlines()[-1])
    assert "numba" not in first["modules"]
    out = json.loads(runs[1].splitlines()[-1])
    assert out["code"] in (0, 1) and out["plugins"] == [] and out["modules"] == []
    assert out["threads"] in (1, None)  # OpenBLAS started no thread of its own
    assert out["collector"][0] and out["collector"][1] > 10_000  # on again, the imports' objects frozen
    called = subprocess.run([sys.executable, "-c", "import sys; from drivetrain.cli import main; "
                             "main(['size', sys.argv[1], '--json'])", axis],
                            env=env, capture_output=True, text=True, check=True).stdout
    assert json.loads("\n".join(runs[1].splitlines()[:-1])) == json.loads(called)


def test_a_thread_count_the_user_set_is_kept(fresh_env: dict[str, str]) -> None:
    env = {**{k: v for k, v in fresh_env.items() if k != "OPENBLAS_NUM_THREADS"}, "OMP_NUM_THREADS": "2"}
    probe = ("import os, sys; from drivetrain.cli import main; sys.argv = ['drivetrain', '--version']; main(); "
             "import numpy; print(os.environ.get('OPENBLAS_NUM_THREADS'), len(os.listdir('/proc/self/task')), "
             "os.cpu_count())")
    if not Path("/proc/self/task").is_dir():
        pytest.skip("no /proc: the thread count cannot be read")
    out = subprocess.run([sys.executable, "-c", probe], env=env, capture_output=True, text=True, check=True).stdout
    setting, threads, cpus = out.split()[-3:]
    assert setting == "None" and int(threads) == min(2, int(cpus))  # OpenBLAS: at most one thread per CPU


@pytest.mark.parametrize("name", EXAMPLES)
def test_a_candidates_details_in_a_batch_are_its_own_to_the_bit(name: str, whole_catalog: tuple[Any, Any]) -> None:
    """``details(ks).column(j)`` (the listing's one kernel call) is what ``details([ks[j]])`` gives alone, for
    passing and failing, fast and too-slow, direct and geared candidates of the whole catalog."""
    motors, gb = whole_catalog
    axis = load_axis(ROOT / "examples" / f"{name}.yaml")
    c = selection.evaluate(axis, duty_cycle(axis), motors, gb, Margins())
    rng = np.random.default_rng(sum(map(ord, name)))
    ks = np.concatenate([np.flatnonzero(c.ok)[:5], np.flatnonzero(~c.ok)[:5],
                         rng.choice(len(c.motor), min(20, len(c.motor)), replace=False)])
    batch = c.details(ks)
    for j, k in enumerate(ks):
        alone, one = c.details([k]), batch.column(j)
        for field in ("required", "available", "margin", "approximate"):
            assert getattr(one, field).keys() == getattr(alone, field).keys()
            assert all(_same_bits(getattr(one, field)[n], getattr(alone, field)[n]) for n in getattr(alone, field))
        assert all(_same_bits(getattr(one, f), getattr(alone, f))
                   for f in ("rms_torque", "peak_torque", "inertia_ratio"))
