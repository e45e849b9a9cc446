"""Mechanisms in SI: each turns load motion and force into speed and torque at its input shaft.

The runtime types (``Mechanism``, ``LinearLoad``, ``RotaryLoad``, the chain's ``ChainLoad``) and the
mechanisms' formulas (``screw``); the axis file's ``mechanism:`` models that build them are
``drivetrain.axis.mechanisms``.
"""

from __future__ import annotations

from drivetrain.physics.mechanisms.base import LinearLoad, Mechanism, RotaryLoad

__all__ = ["LinearLoad", "Mechanism", "RotaryLoad"]
