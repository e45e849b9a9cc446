"""Convergence study: ``drivetrain simulate``'s figures against the step.

Run: ``.venv/bin/python bench/bench_sim_step.py [--refine 1 2 4 8] [examples/*.yaml]``. Prints a markdown table.

For every example that ``simulate`` accepts, the axis is simulated on its own profile (``simulate_axis``)
at the step h of ``default_step`` (step x omega_max <= 0.2) and at h/2, h/4, h/8 (the same tuned loop,
window and reference; only the step changes), and the settling time per stop (load into its window),
the largest following error (motor, as the drive sees it) and the largest load position error are printed
with their deviation
from the finest run. A stop that never settles prints "-". Also printed: h x omega_max and the
wall time of each run (one process, warm kernel; the machine is shared, so times are indicative).
``--selection WINDOW_UM``: instead, the dynamic selection's simulations of examples/belt_dynamic.yaml's 20
best candidates (30 deg margin, every one simulated, settling window WINDOW_UM at the load), each
against the same candidate's full chain at ``default_step`` and at the automatic (converged) step: the
relative change of the settling time per stop that settles in both, and the stops that settle in one
and not the other. The selection's calls are observed by wrapping ``reduction.reduce_for_simulation``
and ``simulation.simulate`` for the run.

The last row per example ("auto") is what ``simulate`` reports with its automatic step (refined
until two runs agree, ``simulation.simulate``), with its step and whether the test passed.
"""

from __future__ import annotations

import argparse
import glob
import math
import time

import numpy as np

from drivetrain.axis.model import load_axis
from drivetrain.dynamics.axis_model import simulate_axis
from drivetrain.dynamics.kernel_io import _omega_max, default_step
from drivetrain.errors import InputError


def _fmt_ms(v: float) -> str:
    return "-" if math.isnan(v) else f"{v * 1e3:.2f}"


def _dev(v: float, ref: float, h: float) -> str:
    if math.isnan(v) or math.isnan(ref):
        return "same" if math.isnan(v) and math.isnan(ref) else "differs"
    d = v - ref
    rel = f"{100 * d / ref:+.1f} %" if ref > 0 else "abs"
    return f"{d * 1e3:+.2f} ms ({rel}, {abs(d) / h:.1f} h)"


def selection(window_um: float) -> None:
    """The selection's lumped runs against the full chain at both steps (module docstring)."""
    import tempfile
    from pathlib import Path
    from typing import Any

    import yaml

    import drivetrain
    from drivetrain.dynamics import reduction, simulation

    data = yaml.safe_load(Path("examples/belt_dynamic.yaml").read_text(encoding="utf-8"))
    data["requirements"].update({"candidates": 20, "stability": {"phase_margin": "30 deg"},
                                 "settling": {"window": f"{window_um} um", "time": "1 ms"}})
    runs: list[tuple[Any, ...]] = []
    full: dict[str, Any] = {}
    reduce, sim = reduction.reduce_for_simulation, simulation.simulate

    def observed_reduce(chain: Any, *a: Any, **k: Any) -> Any:
        full["chain"] = chain
        return reduce(chain, *a, **k)

    def observed_sim(chain: Any, loop: Any, ref: Any, **k: Any) -> Any:
        res = sim(chain, loop, ref, **k)
        runs.append((full["chain"], loop, ref, k, res))
        return res

    reduction.reduce_for_simulation, simulation.simulate = observed_reduce, observed_sim  # type: ignore[assignment]
    try:
        with tempfile.TemporaryDirectory() as folder:
            path = Path(folder, "axis.yaml")
            path.write_text(yaml.safe_dump(data), encoding="utf-8")
            drivetrain.size(str(path))
    finally:
        reduction.reduce_for_simulation, simulation.simulate = reduce, sim  # type: ignore[assignment]
    sel, plain, conv, steps = [], [], [], []
    for chain, loop, ref, k, res in runs:
        kw = {"load_torque": k["load_torque"], "settle_tolerance": k["settle_tolerance"], "check_stability": False}
        auto = sim(chain, loop, ref, **kw)
        sel.append(res.settling_time)
        plain.append(sim(chain, loop, ref, step=default_step(chain, loop), **kw).settling_time)
        conv.append(auto.settling_time)
        steps.append((k["step"], auto.step, auto.step_converged))
    s_sel, s_plain, s_conv = (np.concatenate(a) for a in (sel, plain, conv))
    print(f"window {window_um:g} um: {len(runs)} candidates, {s_conv.size} stops; steps: selection "
          f"{min(x[0] for x in steps) * 1e6:.1f}-{max(x[0] for x in steps) * 1e6:.1f} us, automatic "
          f"{min(x[1] for x in steps) * 1e6:.2f}-{max(x[1] for x in steps) * 1e6:.2f} us, "
          f"converged {sum(bool(x[2]) for x in steps)} of {len(steps)}")
    for name, got in (("selection (lumped, reduced_step)", s_sel), ("full chain at default_step", s_plain)):
        both = ~np.isnan(got) & ~np.isnan(s_conv) & (s_conv > 0)
        d = 100 * (got[both] / s_conv[both] - 1)
        one_only = int(np.sum(np.isnan(got) != np.isnan(s_conv)))
        print(f"  {name} vs full chain converged: settling median {np.median(d):+.1f} % "
              f"({d.min():+.1f}..{d.max():+.1f} %), settles in one only: {one_only}")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("files", nargs="*")
    ap.add_argument("--refine", type=int, nargs="+", default=[1, 2, 4, 8])
    ap.add_argument("--selection", type=float, metavar="WINDOW_UM")
    args = ap.parse_args()
    if args.selection is not None:
        selection(args.selection)
        return
    files = args.files or sorted(glob.glob("examples/*.yaml"))
    print("| example | step | h [us] | h w_max | settling per stop [ms] | vs finest | max following error [mrad] "
          "| vs finest | max load error [mrad] | run [s] |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for f in files:
        axis = load_axis(f)
        try:
            base = simulate_axis(axis)
        except InputError as exc:
            print(f"| {f} | not accepted: {exc} |||||||||")
            continue
        h0 = default_step(base.chain, base.loop) if base.loop is not None else float(base.step)
        w = _omega_max(base.chain)
        runs: list[tuple[str, float, object, float]] = []
        for k in args.refine:
            t0 = time.perf_counter()
            r = simulate_axis(axis, step=h0 / k)
            runs.append((f"h/{k}", h0 / k, r, time.perf_counter() - t0))
        t0 = time.perf_counter()
        auto = simulate_axis(axis)
        runs.append((f"auto{'' if auto.step_converged else ' (not converged)'}", auto.step, auto,
                     time.perf_counter() - t0))
        fine = runs[-2][2]
        for label, h, r, dt in runs:
            assert hasattr(r, "settling_time")
            st = np.asarray(r.settling_time, dtype=float)
            dev = ", ".join(_dev(float(a), float(b), h0) for a, b in zip(st, fine.settling_time, strict=True))
            fe_dev = 100 * (r.max_following_error / fine.max_following_error - 1)
            print(f"| {f.split('/')[-1]} | {label} | {h * 1e6:.3g} | {h * w:.3f} | "
                  f"{', '.join(_fmt_ms(float(v)) for v in st) or 'no stop'} | {dev} | "
                  f"{r.max_following_error * 1e3:.4g} | {fe_dev:+.2f} % | {r.max_load_error * 1e3:.4g} | "
                  f"{dt:.3f} |")


if __name__ == "__main__":
    main()
