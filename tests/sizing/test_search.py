"""The smallest-first search (``sizing.search``): where the best candidate is known to assemble but its
brake's holding torque is not known, the search goes on only through motors whose brake is known."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

from drivetrain.axis.model import load_axis
from drivetrain.duty.cycle import duty_cycle
from drivetrain.sizing import search
from drivetrain.sizing.candidates import BRAKE_BIT, KNOWN_FIRST
from drivetrain.sizing.selection import select

EXAMPLE = Path(__file__).parents[2] / "examples" / "ball_screw.yaml"


def test_after_a_pick_with_an_unknown_brake_only_motors_with_a_known_brake_are_searched(
        monkeypatch: pytest.MonkeyPatch) -> None:
    axis = load_axis(EXAMPLE)
    duty = duty_cycle(axis)
    assert axis.spec.motor is not None
    spec, margins = axis.spec.motor.select, axis.spec.motor.margins
    assert spec is not None
    chunks: list[Any] = []
    evaluate_chunk = search._evaluate_chunk

    def recording(ev: Any, tb: Any, bounds: Any, members: Any) -> Any:
        found = evaluate_chunk(ev, tb, bounds, members)
        chunks.append((tb, members, found))
        return found

    monkeypatch.setattr(search, "_evaluate_chunk", recording)
    answer = search.select_first({}, axis, duty, spec, margins)
    reference = select(axis, duty, spec, margins)
    # the same pick as the whole catalog's ranking: the example's pick holds on a brake the catalog lacks
    pick, ref = answer.summary.selected, reference.summary.selected
    assert pick is not None and ref is not None
    assert (pick.motor, pick.gearbox, pick.ratio) == (ref.motor, ref.gearbox, ref.ratio)
    assert "motor_brake" in pick.unknown
    first = next(i for i, (_, _, found) in enumerate(chunks) if found is not None and np.any(found[0].ok))
    c = chunks[first][2][0]
    best = search.ranked(c, chunks[first][2][1], chunks[first][2][2], "smallest", duty)[0]
    assert int(c.unknown[best]) & KNOWN_FIRST == BRAKE_BIT
    later = [members for _, members, _ in chunks[first + 1:]]
    tb = chunks[first][0]
    # every chunk after the first passing one holds only motors whose brake's holding torque is known
    assert all(np.all(np.isfinite(tb.motors.brake_holding_torque[m])) for m in later)
