"""Benchmark: catalog selection with the drive post-pass against the same selection without it.

One run, the same axis and catalog (every shipped motor, direct and behind every gearbox row): the
motor/gearbox selection alone (``selection.select``), then the selection plus the drive rule and
post-pass (``drive_select.orderable``: the selected motor must have an orderable drive, walking the
ranking where it has not; ``drive_select.attach_drives``: a drive per listed candidate, the selected
motor's electrical and regen blocks). Twice: ``unknown: flag`` (the default) and ``unknown: fail``
(where the walk passes over every motor whose drive cannot be checked). Reported as the ratio of
the medians; the target is at most 2.
Run: ``.venv/bin/python bench/bench_select_drives.py``.
"""

from __future__ import annotations

import os
import statistics
import tempfile
import time
from typing import Any

os.environ.setdefault("DRIVETRAIN_DATA_DIR", tempfile.mkdtemp(prefix="drivetrain-bench-"))

from drivetrain.axis.model import parse_axis
from drivetrain.duty.cycle import duty_cycle
from drivetrain.sizing.drive_select import attach_drives, orderable
from drivetrain.sizing.selection import select

AXIS: dict[str, Any] = {
    "mechanism": {"type": "ball_screw", "lead": "10 mm", "diameter": "20 mm", "length": "0.8 m",
                  "incline": "90 deg", "load": {"mass": 25, "friction": 0.05}},
    "profile": [{"move": f"{(k % 5 + 1) * 20 * (-1) ** k} mm", "time": "0.4 s", "shape": "s_curve",
                 "jerk_fraction": 0.5} for k in range(10)],
    "motor": {"select": {"objective": "smallest"}},
}
POINTS = 143  # 10 moves x 7 pieces: about 10,000 samples
RUNS = 5


def main() -> None:
    for policy in ("flag", "fail"):
        run({**AXIS, "motor": {"select": {**AXIS["motor"]["select"], "unknown": policy}}}, policy)


def run(data: dict[str, Any], policy: str) -> None:
    axis = parse_axis(data)
    duty = duty_cycle(axis, POINTS)
    spec = axis.spec.motor.select if axis.spec.motor is not None else None
    assert spec is not None
    margins = axis.spec.motor.margins if axis.spec.motor is not None else None
    assert margins is not None
    select(axis, duty, spec, margins)  # compile or load the compiled pass, warm the catalog cache
    without, with_drives = [], []
    for _ in range(RUNS):
        t0 = time.perf_counter()
        select(axis, duty, spec, margins)
        without.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        chosen = orderable(axis, duty, select(axis, duty, spec, margins))
        attach_drives(axis, duty, chosen, margins)
        with_drives.append(time.perf_counter() - t0)
    a, b = statistics.median(without), statistics.median(with_drives)
    sel = chosen.summary
    print(f"unknown: {policy}; samples per cycle: {len(duty.t)}; candidates evaluated: {sel.evaluated}; "
          f"listed with a drive block: {len(chosen.listed)}; "
          f"passed over for the drive: {sel.drive_passed_over_count or 0}")
    print(f"  selection without drives: {a * 1e3:.1f} ms (median of {RUNS})")
    print(f"  selection with drives:    {b * 1e3:.1f} ms (median of {RUNS})")
    print(f"  ratio with / without drives: {b / a:.2f} (target <= 2)")
    d = None if sel.selected is None else sel.selected.drive
    print(f"  selected: {None if sel.selected is None else sel.selected.motor} drive: {getattr(d, 'id', None)} "
          f"({getattr(d, 'status', None)})")


if __name__ == "__main__":
    main()
