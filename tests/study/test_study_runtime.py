"""The embedded cluster's process settings and the search bounds shared by the variants of one motion.

* The workers are forked with the calling process's objects frozen for the collector; the calling
  process is left as it was (nothing of its own stays frozen after the study).
* The workers keep freed memory (glibc ``mallopt``); the settings are accepted where glibc is.
* ``search_bounds`` keeps the max-speed halves of one motion with the tables: a variant's bounds
  with the kept halves equal, to the bit, those computed afresh.
"""

from __future__ import annotations

import ctypes.util
import gc
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

from drivetrain.axis.model import load_axis
from drivetrain.sizing.search import search_bounds, selection_tables
from drivetrain.study import sweep
from drivetrain.study.batch import Engine

BASE = Path(__file__).parents[2] / "examples" / "ball_screw.yaml"
GRID = {"study": 1, "name": "runtime grid", "base": str(BASE),
        "parameters": {"mechanism.load.mass": {"values": [10, 30], "unit": "kg"},
                       "profile[0].time": {"values": [0.4, 0.7], "unit": "s"}}}


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="workers are forked on Linux only")
def test_calling_process_left_unfrozen(tmp_path: Path) -> None:
    p = tmp_path / "grid.yaml"
    p.write_text(yaml.safe_dump(GRID, sort_keys=False), encoding="utf-8")
    before = gc.get_freeze_count()
    df = sweep(p, workers=1, batch=2).table
    assert len(df) == 4 and df["error"].eq("").all()
    assert gc.get_freeze_count() == before
    assert gc.isenabled()


@pytest.mark.skipif(not (sys.platform.startswith("linux") and ctypes.util.find_library("c")),
                    reason="glibc's mallopt")
def test_malloc_settings_accepted() -> None:
    # in a process of its own: the settings are for the study's workers, not for the test process (whose later
    # tests start and kill worker processes of their own)
    code = "from drivetrain.study.runner import _keep_freed_memory as keep; raise SystemExit(0 if keep() else 3)"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr


@pytest.mark.parametrize(("mass", "lead"), [(5.0, None), (40.0, None), (22.5, "5 mm"), (25.0, "20 mm")])
def test_search_bounds_kept_halves_equal_fresh(mass: float, lead: str | None) -> None:
    """Kept from the base axis (25 kg; its lead): the same motion, or another lead (another key)."""
    base = load_axis(BASE)
    spec = base.spec.motor
    assert spec is not None and spec.select is not None
    engine = Engine()
    data = yaml.safe_load(BASE.read_text(encoding="utf-8"))
    data["mechanism"]["load"]["mass"] = f"{mass} kg"
    if lead is not None:
        data["mechanism"]["lead"] = lead
    from drivetrain.axis.model import parse_axis

    axis = parse_axis(data)
    tb = selection_tables(engine.context.tables, axis, spec.select, engine.context.duty(axis))
    # the halves kept from another variant of the same motion (the base axis's load)
    search_bounds(tb, engine.context.duty(base), spec.margins, spec.select)
    assert tb._speed
    kept = search_bounds(tb, engine.context.duty(axis), spec.margins, spec.select)
    tb._speed.clear()
    fresh = search_bounds(tb, engine.context.duty(axis), spec.margins, spec.select)
    np.testing.assert_array_equal(kept.pair, fresh.pair)
    np.testing.assert_array_equal(kept.row, fresh.row)
    assert kept.pair.dtype == fresh.pair.dtype and kept.row.shape == fresh.row.shape
