"""Speed-torque curve points of a catalog motor, as the vendor prints them (or a user imports them)."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


class Curve(NamedTuple):
    """A motor's speed-torque curve points: speed [rad/s] ascending, torques [N m] (NaN: not given)."""

    speed: FloatArray
    continuous: FloatArray
    peak: FloatArray

    @classmethod
    def from_points(cls, points: list[tuple[float, float | None, float | None]]) -> Curve:
        """Build from (speed, continuous, peak) tuples; None becomes NaN; sorted by speed."""
        pts = sorted(points, key=lambda p: p[0])
        arr = np.array(
            [[p[0], np.nan if p[1] is None else p[1], np.nan if p[2] is None else p[2]] for p in pts],
            dtype=float,
        ).reshape(-1, 3)
        return cls(arr[:, 0], arr[:, 1], arr[:, 2])

    def to_dict(self) -> dict[str, list[float | None]]:
        """JSON-ready dict with unit-suffixed keys; NaN becomes None."""

        def plain(a: FloatArray) -> list[float | None]:
            return [None if np.isnan(x) else float(x) for x in a]

        return {
            "speed_rad_s": plain(self.speed),
            "continuous_torque_Nm": plain(self.continuous),
            "peak_torque_Nm": plain(self.peak),
        }
