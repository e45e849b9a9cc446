"""Axis-file inputs for the mechanism's own limits, life and stiffness (docs/axis-file.md, "Mechanism limits").

Each block is optional; a check runs only where its ratings are given (a rating is never
guessed). Values go through the unit parser into SI like every other key.

- ``mechanism.screw``: shaft geometry and mounting for buckling, critical speed, DN and stiffness.
- ``mechanism.nut``: the ball nut's ratings (C_a, C_0a), preload and stiffness for its L10 life.
- ``mechanism.belt``: belt ratings, pretension and layout for the tension check and the belt spring.
- ``mechanism.rack``: the rack and pinion's permissible feed force and mesh stiffness.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

from drivetrain.fields import Angle, ForcePos, Length, LengthNonNeg, Spec, Time, quantity

StiffnessPos = Annotated[float, quantity("linear_stiffness", gt=0.0)]
Factor = Annotated[float, Field(ge=1.0, le=10.0)]

DEFAULT_REQUIRED_LIFE = 20_000.0 * 3600.0
"""[s] Life a nut or guide must reach when the axis file names none (20 000 h); set your own."""


class ScrewLimitsSpec(Spec):
    """``mechanism.screw``: ``{root_diameter, mounting, unsupported_length?, dn_limit?, ...}``.

    ``root_diameter`` d_1 (thread minor diameter); ``mounting`` of the shaft ends (THK's four
    arrangements); ``unsupported_length`` between the supports (default ``mechanism.length``);
    ``home_position`` the nut's distance from the fixed (thrust) bearing at load position 0
    (default 0: positions are measured from the fixed bearing); ``ball_circle_diameter`` for
    the DN value (default ``mechanism.diameter``) with the catalog's ``dn_limit`` [mm/min];
    ``support_bearing_stiffness`` and ``housing_stiffness`` in series with the shaft and nut.
    """

    root_diameter: Length
    mounting: Literal["fixed_free", "supported_supported", "fixed_supported", "fixed_fixed"] = "fixed_supported"
    unsupported_length: Length | None = None
    home_position: LengthNonNeg = 0.0
    ball_circle_diameter: Length | None = None
    dn_limit: float | None = Field(default=None, gt=0.0)
    youngs_modulus: Annotated[float, quantity("pressure", gt=0.0)] = 206e9
    support_bearing_stiffness: StiffnessPos | None = None
    housing_stiffness: StiffnessPos | None = None


class NutSpec(Spec):
    """``mechanism.nut``: ``{C_a, C_0a?, preload?, load_factor?, required_life?, stiffness?}``.

    ``C_a`` basic dynamic and ``C_0a`` static axial load ratings (catalog), ``preload`` of a
    preloaded nut, ``load_factor`` f_w (1.0-1.2 smooth, 1.2-1.5 normal, 1.5-2.0 with impact,
    MiSUMi), ``required_life`` (default 20 000 h), ``static_safety`` the f_s the static check
    requires (default 1), ``stiffness`` the nut's axial rigidity (catalog, at its preload).
    """

    C_a: ForcePos
    C_0a: ForcePos | None = None
    preload: Annotated[float, quantity("force", ge=0.0)] = 0.0
    load_factor: Factor = 1.0
    required_life: Time = DEFAULT_REQUIRED_LIFE
    static_safety: Factor = 1.0
    stiffness: StiffnessPos | None = None


class BeltDriveSpec(Spec):
    """``mechanism.belt``: ``{specific_stiffness?, permissible_tension?, pretension?, centre_distance?, ...}``.

    ``specific_stiffness`` c_spec [N] of the belt for its width (catalog C_spez), or
    ``permissible_tension`` with ``strain_at_permissible`` (0.004: c_spec = F_adm / 0.004, the
    ELATECH tables); ``pretension`` per span (default: the largest pull, ELATECH's F_TV >= F_U);
    ``centre_distance`` between drive pulley and idler (required for the stiffness);
    ``layout`` ``loop`` or ``omega``; ``home_position`` the carriage's distance from the drive
    pulley at load position 0; ``wrap_angle`` of the belt on the drive pulley (180 deg).
    """

    specific_stiffness: ForcePos | None = None
    permissible_tension: ForcePos | None = None
    strain_at_permissible: float = Field(default=0.004, gt=0.0, lt=0.1)
    pretension: Annotated[float, quantity("force", ge=0.0)] | None = None
    centre_distance: Length | None = None
    layout: Literal["loop", "omega"] = "loop"
    home_position: LengthNonNeg = 0.0
    clamp_offset: LengthNonNeg = 0.0
    wrap_angle: Angle = 3.141592653589793


class RackSpec(Spec):
    """``mechanism.rack``: ``{permissible_force?, application_factor?, face_width?, mesh_stiffness?, ...}``.

    ``permissible_force`` the vendor's permissible feed (tangential) force for the pinion and rack,
    ``application_factor`` K_A (default 1), ``pressure_angle`` (20 deg) and ``helix_angle`` (0),
    ``face_width`` with ``mesh_stiffness`` c_gamma per unit width [N/m per m] for the mesh
    spring (default 20 N/(mm um), ISO 6336-1 for solid steel spur gears).
    """

    permissible_force: ForcePos | None = None
    application_factor: Factor = 1.0
    pressure_angle: Angle = 0.3490658503988659
    helix_angle: Angle = 0.0
    face_width: Length | None = None
    mesh_stiffness: Annotated[float, quantity("pressure", gt=0.0)] = 20e9


__all__ = ["DEFAULT_REQUIRED_LIFE", "BeltDriveSpec", "NutSpec", "RackSpec", "ScrewLimitsSpec"]
