r"""The cascaded servo loop as drives run it, its tuning and its frequency responses.

Structure (motor-side feedback, each loop at its own sample time):

    position ref --(+)-- Kv -- (+ velocity FF) --(+)-- PI: kp (1 + 1/(Ti s)) -- notch -- low-pass
                 ^ encoder (quantised)             ^ speed = encoder difference / T_v
    -- (+ acceleration FF J_ff a_ref) -- torque limit -- current loop 1/(1 + s/w_c) -- plant

Units: kp [N m s/rad], Ti [s], Kv [1/s], torques [N m], sample times [s], bandwidths [Hz].

The sampled loops are analysed in continuous time with their delays: the velocity loop sees the
speed estimate's half sample, the zero-order hold's half sample and half a current-loop sample,
tau_v = T_v + T_c / 2; the position loop adds T_p / 2 (Franklin, Powell, Workman, *Digital
Control of Dynamic Systems*, 3rd ed., sec. 6.3: a ZOH acts as a delay of half a sample). Margins
and Bode data use the exact delay e^{-s tau}; the stability verdict uses the closed-loop poles with
a third-order Pade approximation of each delay.

Tuning rule (documented choice; Ellis, *Control System Design Guide*, 4th ed. (2012), chapters
"Compliance and Resonance" and "Position-Control Loops"):
- velocity bandwidth f_v = min(requested, a fraction (default 0.5) of the first anti-resonance,
  current-loop bandwidth / 4, the bandwidth at which the loop delay costs 20 deg of phase);
- kp = 2 pi f_v J_total (crossover of the rigid-body loop at f_v);
- Ti = 4 / (2 pi f_v) (the PI zero a factor 4 below the crossover);
- Kv = 2 pi f_v / 4 (position bandwidth a quarter of the velocity bandwidth);
- feed-forward: velocity 100 %, acceleration J_total (the rigid inertia);
- when no bandwidth is requested and the result is not stable (a resonance close to the loop
  delay), f_v is lowered in steps of 20 % until the closed-loop poles are stable.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from drivetrain.dynamics.chain import Chain
from drivetrain.dynamics.filters import Notch, lowpass_response, propose_notch
from drivetrain.errors import InputError

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


@dataclass(frozen=True)
class ServoLoop:
    """Gains and settings of the cascaded loop (SI).

    Attributes:
        velocity_kp: PI proportional gain [N m s/rad].
        velocity_ti: PI integral time [s] (``math.inf``: P only).
        position_kv: position gain [1/s] ((rad/s) per rad of error).
        current_bandwidth_hz: bandwidth of the current (torque) loop, a first-order lag [Hz].
        velocity_ff: velocity feed-forward fraction [-] (1 = the reference speed in full).
        acceleration_ff: acceleration feed-forward inertia [kg m^2] (torque = it * reference accel).
        notch: optional notch on the torque command.
        lowpass_hz: optional first-order low-pass on the torque command [Hz].
        torque_limit: motor torque limit [N m] (``math.inf``: none).
        current_sample_time, velocity_sample_time, position_sample_time: loop periods [s].
        encoder_resolution: position quantum [rad] (2 pi / counts per rev; 0: ideal).
        notes: why tuning chose what it chose.
    """

    velocity_kp: float
    velocity_ti: float
    position_kv: float
    current_bandwidth_hz: float = 2000.0
    velocity_ff: float = 1.0
    acceleration_ff: float = 0.0
    notch: Notch | None = None
    lowpass_hz: float | None = None
    torque_limit: float = math.inf
    current_sample_time: float = 62.5e-6
    velocity_sample_time: float = 125e-6
    position_sample_time: float = 250e-6
    encoder_resolution: float = 0.0
    notes: tuple[str, ...] = field(default=(), compare=False)

    def __post_init__(self) -> None:
        p = "dynamics.loop"
        for name, strict in (("velocity_kp", True), ("position_kv", False), ("current_bandwidth_hz", True),
                             ("torque_limit", True), ("current_sample_time", True),
                             ("velocity_sample_time", True), ("position_sample_time", True)):
            v = getattr(self, name)
            ok = not math.isnan(v) and (v > 0 if strict else v >= 0)
            if not ok or (name != "torque_limit" and math.isinf(v)):
                raise InputError(f"{p}.{_USER_KEY.get(name, name)}", "must be > 0" if strict else "must be >= 0", v)
        if math.isnan(self.velocity_ti) or self.velocity_ti <= 0:
            raise InputError(f"{p}.velocity_ti", "must be > 0 s (inf for no integral action)", self.velocity_ti)
        for name in ("velocity_ff", "acceleration_ff", "encoder_resolution"):
            v = getattr(self, name)
            if not math.isfinite(v) or v < 0:
                raise InputError(f"{p}.{name}", "must be a finite number >= 0", v)
        if self.lowpass_hz is not None and not (math.isfinite(self.lowpass_hz) and self.lowpass_hz > 0):
            raise InputError(f"{p}.lowpass", "must be > 0 Hz", self.lowpass_hz)

    @property
    def velocity_delay(self) -> float:
        """Effective delay in the velocity loop [s]: T_v + T_c / 2."""
        return self.velocity_sample_time + 0.5 * self.current_sample_time

    @property
    def position_delay(self) -> float:
        """Additional delay in the position loop [s]: T_p / 2."""
        return 0.5 * self.position_sample_time

    def with_(self, **changes: Any) -> ServoLoop:
        """A copy with some settings changed."""
        values = {k: getattr(self, k) for k in self.__dataclass_fields__}
        values.update(changes)
        return ServoLoop(**values)

    def to_dict(self) -> dict[str, Any]:
        """Plain-JSON form (the notch as a mapping)."""
        d = asdict(self)
        d["notes"] = list(self.notes)
        return d


_USER_KEY = {"current_bandwidth_hz": "current_bandwidth", "lowpass_hz": "lowpass"}
"""Axis-file key (``dynamics.loop``) of a ``ServoLoop`` field where the two names differ."""


def tune(
    chain: Chain,
    velocity_bandwidth_hz: float | None = None,
    *,
    fraction_of_anti_resonance: float = 0.5,
    current_bandwidth_hz: float = 2000.0,
    current_sample_time: float = 62.5e-6,
    velocity_sample_time: float = 125e-6,
    position_sample_time: float = 250e-6,
    notch: bool | Notch = False,
    lowpass_hz: float | None = None,
    torque_limit: float = math.inf,
    encoder_resolution: float = 0.0,
) -> ServoLoop:
    """Gains from a requested velocity bandwidth by the module's rule (see the module docstring).

    ``velocity_bandwidth_hz`` None asks for the highest the rule allows. ``notch=True`` adds a
    notch proposed by ``filters.propose_notch`` for the first resonance; a ``Notch`` is used as
    given. The result's ``notes`` say which limit set the bandwidth.
    """
    if velocity_bandwidth_hz is not None and not (velocity_bandwidth_hz > 0 and math.isfinite(velocity_bandwidth_hz)):
        raise InputError("dynamics.loop.velocity_bandwidth", "must be > 0 Hz", velocity_bandwidth_hz)
    if not 0 < fraction_of_anti_resonance <= 1.0:
        raise InputError("dynamics.loop.fraction_of_anti_resonance", "must be in (0, 1]",
                         fraction_of_anti_resonance)
    from drivetrain.dynamics.linear import anti_resonance_frequencies, natural_frequencies

    delay = velocity_sample_time + 0.5 * current_sample_time
    limits: dict[str, float] = {
        "current-loop bandwidth / 4": current_bandwidth_hz / 4.0,
        "loop delay (20 deg of phase)": 20.0 / (360.0 * delay),
    }
    f_ar = math.inf
    if chain.n >= 2:
        f_ar = float(anti_resonance_frequencies(chain)[0])
        limits[f"{fraction_of_anti_resonance:g} x anti-resonance {f_ar:.1f} Hz"] = fraction_of_anti_resonance * f_ar
    limit_name = min(limits, key=lambda k: limits[k])
    f_max = limits[limit_name]
    notes: list[str] = []
    if velocity_bandwidth_hz is None:
        f_v = f_max
        notes.append(f"velocity bandwidth {f_v:.1f} Hz set by {limit_name}")
    elif velocity_bandwidth_hz > f_max:
        f_v = f_max
        notes.append(f"requested velocity bandwidth {velocity_bandwidth_hz:g} Hz lowered to {f_v:.1f} Hz by "
                     f"{limit_name}")
    else:
        f_v = velocity_bandwidth_hz
        notes.append(f"velocity bandwidth {f_v:g} Hz as requested")
    w_v = 2.0 * math.pi * f_v
    j_total = chain.total_inertia
    the_notch: Notch | None = None
    if isinstance(notch, Notch):
        the_notch = notch
    elif notch and chain.n >= 2:
        f_r = float(natural_frequencies(chain)[0])
        the_notch = propose_notch(f_r, f_ar, f_v)
        notes.append(f"notch at {the_notch.center_hz:.1f} Hz, width {the_notch.width_hz:.1f} Hz, depth "
                     f"{the_notch.depth_db:.1f} dB")
    loop = _loop_at(w_v, j_total, current_bandwidth_hz, the_notch, lowpass_hz, torque_limit, current_sample_time,
                    velocity_sample_time, position_sample_time, encoder_resolution, notes)
    if velocity_bandwidth_hz is None and chain.n >= 2:
        # The rule's limits ignore how the resonance interacts with the loop delay: back off in
        # steps of 20 % until the closed loop is stable (at most 20 steps, i.e. down to 1 %).
        for _ in range(20):
            try:
                check_stable(chain, loop)
                break
            except InputError:
                w_v *= 0.8
                if the_notch is not None and not isinstance(notch, Notch):
                    the_notch = propose_notch(float(natural_frequencies(chain)[0]), f_ar, w_v / (2.0 * math.pi))
                loop = _loop_at(w_v, j_total, current_bandwidth_hz, the_notch, lowpass_hz, torque_limit,
                                current_sample_time, velocity_sample_time, position_sample_time,
                                encoder_resolution, [*notes, f"lowered to {w_v / (2 * math.pi):.1f} Hz for a stable "
                                                     "closed loop with the resonance and the loop delay"])
    return loop


def _loop_at(w_v: float, j_total: float, current_bandwidth_hz: float, the_notch: Notch | None,
             lowpass_hz: float | None, torque_limit: float, current_sample_time: float, velocity_sample_time: float,
             position_sample_time: float, encoder_resolution: float, notes: list[str]) -> ServoLoop:
    """Gains of the rule at velocity crossover w_v [rad/s] (see ``tune``)."""
    return ServoLoop(
        velocity_kp=w_v * j_total,
        velocity_ti=4.0 / w_v,
        position_kv=w_v / 4.0,
        current_bandwidth_hz=current_bandwidth_hz,
        velocity_ff=1.0,
        acceleration_ff=j_total,
        notch=the_notch,
        lowpass_hz=lowpass_hz,
        torque_limit=torque_limit,
        current_sample_time=current_sample_time,
        velocity_sample_time=velocity_sample_time,
        position_sample_time=position_sample_time,
        encoder_resolution=encoder_resolution,
        notes=tuple(notes),
    )


# --- small state-space algebra (SISO) ---------------------------------------------------------

@dataclass(frozen=True)
class _SS:
    a: FloatArray
    b: FloatArray
    c: FloatArray
    d: float

    @staticmethod
    def from_tf(num: ArrayLike, den: ArrayLike) -> _SS:
        """Controller canonical form of num(s)/den(s) (the form scipy.signal.tf2ss returns;
        written out here so that tuning does not pay scipy.signal's import time)."""
        nu = np.trim_zeros(np.atleast_1d(np.asarray(num, dtype=float)), "f")
        de = np.trim_zeros(np.atleast_1d(np.asarray(den, dtype=float)), "f")
        if de.size == 0 or nu.size > de.size:
            raise ValueError("improper or empty transfer function")
        nu, de = nu / de[0], de / de[0]
        nu = np.concatenate([np.zeros(de.size - nu.size), nu])
        n = de.size - 1
        d = float(nu[0]) if nu.size else 0.0
        a = np.zeros((n, n))
        if n:
            a[0, :] = -de[1:]
            a[1:, :-1] = np.eye(n - 1)
        b = np.zeros((n, 1))
        if n:
            b[0, 0] = 1.0
        c = (nu[1:] - d * de[1:]).reshape(1, n)
        return _SS(a, b, c, d)

    def then(self, other: _SS) -> _SS:
        """Series connection: ``self`` first, then ``other``."""
        n1, n2 = self.a.shape[0], other.a.shape[0]
        a = np.zeros((n1 + n2, n1 + n2))
        a[:n1, :n1] = self.a
        a[n1:, :n1] = other.b @ self.c
        a[n1:, n1:] = other.a
        b = np.vstack([self.b, other.b * self.d])
        c = np.hstack([other.d * self.c, other.c])
        return _SS(a, b, c, other.d * self.d)

    def feedback(self) -> _SS:
        """Unity negative feedback around ``self``."""
        k = 1.0 / (1.0 + self.d)
        return _SS(self.a - k * self.b @ self.c, k * self.b, k * self.c, k * self.d)


def _pade3(delay: float) -> _SS:
    """Third-order Pade approximation of e^{-s delay}."""
    t = delay
    num = [-(t**3) / 120.0, t * t / 10.0, -t / 2.0, 1.0]
    den = [t**3 / 120.0, t * t / 10.0, t / 2.0, 1.0]
    return _SS.from_tf(num, den)


def plant_speed_model(chain: Chain) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Minimal model motor torque -> motor speed in spring twists and speeds (A, B, C) [SI].

    States: twist of each spring (theta_k - theta_{k+1}) [rad], then every speed [rad/s]; the
    absolute angle (the rigid-body integrator of position) is left out so the model is minimal.
    """
    n = chain.n
    m = n - 1
    a = np.zeros((m + n, m + n))
    b = np.zeros((m + n, 1))
    c = np.zeros((1, m + n))
    jinv = 1.0 / chain.inertia
    for k in range(m):
        a[k, m + k] = 1.0
        a[k, m + k + 1] = -1.0
        kk, dd = chain.stiffness[k], chain.damping[k]
        # spring torque T_k = kk * twist_k + dd * (w_k - w_{k+1}) acts -T_k on k, +T_k on k+1
        a[m + k, k] -= kk * jinv[k]
        a[m + k + 1, k] += kk * jinv[k + 1]
        a[m + k, m + k] -= dd * jinv[k]
        a[m + k, m + k + 1] += dd * jinv[k]
        a[m + k + 1, m + k] += dd * jinv[k + 1]
        a[m + k + 1, m + k + 1] -= dd * jinv[k + 1]
    ground = chain.ground_damping.copy()
    for k, fr in enumerate(chain.friction):
        if fr is not None:
            ground[k] += fr.viscous
    for j in range(n):
        a[m + j, m + j] -= ground[j] * jinv[j]
    b[m, 0] = jinv[0]
    c[0, m] = 1.0
    return a, b, c


def _velocity_open_loop_ss(chain: Chain, loop: ServoLoop) -> _SS:
    kp, ti = loop.velocity_kp, loop.velocity_ti
    pi = _SS.from_tf([kp], [1.0]) if math.isinf(ti) else _SS.from_tf([kp * ti, kp], [ti, 0.0])
    sys = pi
    if loop.notch is not None:
        num, den = loop.notch.continuous()
        sys = sys.then(_SS.from_tf(num, den))
    if loop.lowpass_hz is not None:
        sys = sys.then(_SS.from_tf([1.0], [1.0 / (2 * math.pi * loop.lowpass_hz), 1.0]))
    sys = sys.then(_SS.from_tf([1.0], [1.0 / (2 * math.pi * loop.current_bandwidth_hz), 1.0]))
    sys = sys.then(_pade3(loop.velocity_delay))
    a, b, c = plant_speed_model(chain)
    return sys.then(_SS(a, b, c, 0.0))


_LAST_POLES: list[tuple[Chain, ServoLoop, ComplexArray, ComplexArray]] = []
"""The last chain and loop whose poles were computed (both frozen), with their poles: ``tune`` checks the
loop it returns for stability, and ``analyse_loop`` of that chain and loop needs the same poles."""


def closed_loop_poles(chain: Chain, loop: ServoLoop) -> tuple[ComplexArray, ComplexArray]:
    """Closed-loop poles of the velocity loop and of the position loop [1/s] (delays as Pade-3)."""
    last = _LAST_POLES[0] if _LAST_POLES else None  # one read: another thread may replace it
    if last is not None and last[0] is chain and last[1] is loop:
        return last[2].copy(), last[3].copy()
    p_vel, p_pos = _closed_loop_poles(chain, loop)
    _LAST_POLES[:] = [(chain, loop, p_vel.copy(), p_pos.copy())]
    return p_vel, p_pos


def _closed_loop_poles(chain: Chain, loop: ServoLoop) -> tuple[ComplexArray, ComplexArray]:
    vel_cl = _velocity_open_loop_ss(chain, loop).feedback()
    p_vel = np.asarray(np.linalg.eigvals(vel_cl.a), dtype=complex)
    if loop.position_kv == 0.0:
        return p_vel, p_vel
    outer = _SS.from_tf([loop.position_kv], [1.0, 0.0]).then(_pade3(loop.position_delay)).then(vel_cl)
    # the position loop: Kv/s * delay * velocity closed loop, closed around the motor angle
    p_pos = np.asarray(np.linalg.eigvals(outer.feedback().a), dtype=complex)
    return p_vel, p_pos


def check_stable(chain: Chain, loop: ServoLoop) -> None:
    """Raise ``InputError`` (field ``dynamics.control``) when the gain set gives an unstable loop.

    The message names the growing mode's frequency and the likely fix instead of letting a
    simulation produce NaN.
    """
    given = "gains as given" in loop.notes
    with np.errstate(all="ignore"):
        try:
            p_vel, p_pos = closed_loop_poles(chain, loop)
        except np.linalg.LinAlgError:
            p_vel = p_pos = np.array([complex("nan")])
    if not (np.all(np.isfinite(p_vel)) and np.all(np.isfinite(p_pos))):
        raise InputError(
            "dynamics.loop",
            "the closed loop cannot be computed (a gain overflows the state-space model); "
            + ("give gains of a realistic size" if given else "lower velocity_bandwidth"),
            {"velocity_kp": loop.velocity_kp, "velocity_ti": loop.velocity_ti, "position_kv": loop.position_kv},
        )
    for name, poles in (("velocity", p_vel), ("position", p_pos)):
        worst = poles[np.argmax(poles.real)]
        scale = max(1.0, float(np.max(np.abs(poles))))
        if worst.real > 1e-9 * scale:
            f = abs(worst.imag) / (2 * math.pi)
            if not given:
                # The gains came from the tuning rule: name what the user can change.
                hint = ("the gains tuned for this velocity bandwidth do not hold the resonance: set a lower "
                        "dynamics.loop.velocity_bandwidth, or notch: true")
            elif name == "velocity":
                hint = "lower velocity_kp or the velocity bandwidth, or add a notch at the resonance"
            else:
                hint = "lower position_kv (keep it below a quarter of the velocity bandwidth in rad/s)"
            raise InputError(
                "dynamics.loop",
                f"the {name} loop is unstable: a closed-loop pole at s = {worst.real:.4g} {worst.imag:+.4g}j 1/s "
                f"grows {'with an oscillation at ' + format(f, '.1f') + ' Hz' if f > 0 else 'without oscillation'}; "
                f"{hint}",
                {"velocity_kp": loop.velocity_kp, "velocity_ti": loop.velocity_ti, "position_kv": loop.position_kv},
            )


# --- frequency responses ----------------------------------------------------------------------

@dataclass(frozen=True)
class Margins:
    """Stability margins of an open loop."""

    gain_margin: float
    phase_margin_deg: float
    gain_crossover_hz: float
    phase_crossover_hz: float

    @property
    def gain_margin_db(self) -> float:
        """Gain margin [dB]."""
        return 20 * math.log10(self.gain_margin) if 0 < self.gain_margin < math.inf else math.inf

    def to_dict(self) -> dict[str, float]:
        """Plain dict, keys with units."""
        return {"gain_margin": self.gain_margin, "gain_margin_dB": self.gain_margin_db,
                "phase_margin_deg": self.phase_margin_deg, "gain_crossover_Hz": self.gain_crossover_hz,
                "phase_crossover_Hz": self.phase_crossover_hz}


def margins(freq_hz: ArrayLike, open_loop: ArrayLike) -> Margins:
    """Gain and phase margins from open-loop frequency-response data.

    Phase margin: over all gain crossovers (|L| = 1), the smallest angular distance between L and
    the critical point -1 [deg] (180 deg + phase for the usual single crossover with phase in
    (-360, 0]; with a lightly damped resonance the loop crosses unity several times, and the
    distance is what a reader needs; stability itself is judged from the closed-loop poles). Gain
    margin: the smallest 1/|L| over the phase crossovers (phase = -180 deg mod 360) where |L| < 1.
    The phase is unwrapped from the lowest frequency; crossings are interpolated in log frequency.
    """
    f = np.asarray(freq_hz, dtype=float)
    lval = np.asarray(open_loop, dtype=complex)
    mag = np.abs(lval)
    ph = np.degrees(np.unwrap(np.angle(lval)))
    lf = np.log(f)
    pm, f_gc = math.inf, math.nan
    lm = np.log(mag)
    for k in np.nonzero(np.sign(lm[:-1]) != np.sign(lm[1:]))[0]:
        x = lm[k] / (lm[k] - lm[k + 1])
        fc = math.exp(lf[k] + x * (lf[k + 1] - lf[k]))
        pc = ph[k] + x * (ph[k + 1] - ph[k])
        wrapped = (pc + 180.0) % 360.0 - 180.0  # phase in [-180, 180)
        margin = 180.0 - abs(wrapped)
        if margin < pm:
            pm, f_gc = margin, fc
    gm, f_pc = math.inf, math.nan
    shifted = (ph + 180.0) / 360.0
    turns = np.floor(shifted)
    for k in np.nonzero(turns[:-1] != turns[1:])[0]:
        level = max(turns[k], turns[k + 1])
        x = (level - shifted[k]) / (shifted[k + 1] - shifted[k])
        fpc = math.exp(lf[k] + x * (lf[k + 1] - lf[k]))
        mpc = math.exp(lm[k] + x * (lm[k + 1] - lm[k]))
        if mpc < 1.0 and 1.0 / mpc < gm:
            gm, f_pc = 1.0 / mpc, fpc
    return Margins(float(gm), float(pm), float(f_gc), float(f_pc))


def bandwidth_hz(freq_hz: ArrayLike, closed_loop: ArrayLike) -> float:
    """-3 dB bandwidth of a closed loop [Hz]: the first frequency where |T| drops below 1/sqrt(2)."""
    f = np.asarray(freq_hz, dtype=float)
    mag = np.abs(np.asarray(closed_loop, dtype=complex))
    below = np.nonzero(mag < 1.0 / math.sqrt(2.0))[0]
    if below.size == 0:
        return math.inf
    k = int(below[0])
    if k == 0:
        return float(f[0])
    y0, y1 = math.log(mag[k - 1]), math.log(mag[k])
    x = (math.log(1 / math.sqrt(2)) - y0) / (y1 - y0)
    return float(math.exp(math.log(f[k - 1]) + x * (math.log(f[k]) - math.log(f[k - 1]))))


@dataclass(frozen=True)
class LoopAnalysis:
    """Frequency responses and margins of the cascaded loop."""

    freq_hz: FloatArray
    plant: ComplexArray
    velocity_open: ComplexArray
    velocity_closed: ComplexArray
    position_open: ComplexArray
    position_closed: ComplexArray
    velocity_margins: Margins
    position_margins: Margins
    velocity_bandwidth_hz: float
    position_bandwidth_hz: float
    stable: bool
    poles: ComplexArray

    def bode(self) -> dict[str, FloatArray]:
        """Bode data: ``freq_Hz`` and ``<response>_dB`` / ``<response>_deg`` for every response."""
        out: dict[str, FloatArray] = {"freq_Hz": self.freq_hz}
        for name in ("plant", "velocity_open", "velocity_closed", "position_open", "position_closed"):
            h = getattr(self, name)
            out[f"{name}_dB"] = 20.0 * np.log10(np.abs(h))
            out[f"{name}_deg"] = np.degrees(np.unwrap(np.angle(h)))
        return out

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary (margins, bandwidths, stability) without the curves."""
        return {"stable": self.stable,
                "velocity_margins": self.velocity_margins.to_dict(),
                "position_margins": self.position_margins.to_dict(),
                "velocity_bandwidth_Hz": self.velocity_bandwidth_hz,
                "position_bandwidth_Hz": self.position_bandwidth_hz}

    def plot(self) -> Any:
        """Bode plot of the open and closed loops (matplotlib Figure)."""
        import matplotlib

        matplotlib.use("Agg", force=False)
        import matplotlib.pyplot as plt

        fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(8, 6))
        b = self.bode()
        for name in ("plant", "velocity_open", "velocity_closed", "position_closed"):
            ax1.semilogx(self.freq_hz, b[f"{name}_dB"], label=name.replace("_", " "))
            ax2.semilogx(self.freq_hz, b[f"{name}_deg"])
        ax1.set_ylabel("magnitude [dB]")
        ax2.set_ylabel("phase [deg]")
        ax2.set_xlabel("frequency [Hz]")
        ax1.legend()
        ax1.grid(True, which="both")
        ax2.grid(True, which="both")
        return fig


def default_frequencies(chain: Chain, loop: ServoLoop, points: int = 2000) -> FloatArray:
    """Log-spaced grid from 0.1 Hz to the velocity loop's Nyquist frequency, refined around modes."""
    from drivetrain.dynamics.linear import anti_resonance_frequencies, natural_frequencies

    f_hi = 0.5 / loop.velocity_sample_time
    grid = np.geomspace(0.1, f_hi, points)
    extra = [grid]
    for f in np.concatenate([natural_frequencies(chain), anti_resonance_frequencies(chain)]):
        if 0.1 < f < f_hi:
            extra.append(f * np.geomspace(0.95, 1.05, 201))
    f = np.sort(np.concatenate(extra))
    return f[np.concatenate([[True], np.diff(f) > 0])]  # np.unique's result, without its import of numpy.ma


def analyse_loop(chain: Chain, loop: ServoLoop, freq_hz: ArrayLike | None = None) -> LoopAnalysis:
    """Open- and closed-loop frequency responses, margins, bandwidths and stability.

    Velocity loop: L_v = PI * notch * low-pass * current lag * e^{-s tau_v} * P(s), with P the
    chain's motor torque -> motor speed. Position loop: L_p = Kv e^{-s T_p/2} T_v(s) / s with
    T_v = L_v / (1 + L_v) (feed-forward does not change stability and is left out).
    """
    from drivetrain.dynamics.linear import frequency_response

    f = default_frequencies(chain, loop) if freq_hz is None else np.asarray(freq_hz, dtype=float)
    s = 2j * math.pi * f
    plant = frequency_response(chain, f, "motor_torque", "motor_speed")
    c = loop.velocity_kp * (1.0 + (0.0 if math.isinf(loop.velocity_ti) else 1.0 / (loop.velocity_ti * s)))
    filt = np.ones_like(s)
    if loop.notch is not None:
        filt = filt * loop.notch.response(f)
    if loop.lowpass_hz is not None:
        filt = filt * lowpass_response(loop.lowpass_hz, f)
    cur = lowpass_response(loop.current_bandwidth_hz, f)
    lv = c * filt * cur * np.exp(-s * loop.velocity_delay) * plant
    tv = lv / (1.0 + lv)
    lp = loop.position_kv * np.exp(-s * loop.position_delay) * tv / s
    tp = lp / (1.0 + lp)
    p_vel, p_pos = closed_loop_poles(chain, loop)
    poles = np.concatenate([p_vel, p_pos])
    scale = max(1.0, float(np.max(np.abs(poles))))
    stable = bool(np.max(poles.real) <= 1e-9 * scale)
    return LoopAnalysis(f, plant, lv, tv, lp, tp, margins(f, lv), margins(f, lp), bandwidth_hz(f, tv),
                        bandwidth_hz(f, tp), stable, poles)


def notch_effect(chain: Chain, loop: ServoLoop, notch: Notch | None = None) -> dict[str, Any]:
    """The loop's margins and bandwidths without and with a notch (proposed when not given)."""
    from drivetrain.dynamics.linear import anti_resonance_frequencies, natural_frequencies

    base = loop.with_(notch=None)
    without = analyse_loop(chain, base)
    if notch is None:
        f_r = float(natural_frequencies(chain)[0])
        f_ar = float(anti_resonance_frequencies(chain)[0])
        notch = propose_notch(f_r, f_ar, max(without.velocity_margins.gain_crossover_hz, 1e-3)
                              if math.isfinite(without.velocity_margins.gain_crossover_hz) else f_ar / 2)
    with_ = analyse_loop(chain, base.with_(notch=notch))
    return {"notch": {"center_Hz": notch.center_hz, "width_Hz": notch.width_hz, "depth": notch.depth,
                      "depth_dB": notch.depth_db},
            "without": without.to_dict(), "with": with_.to_dict()}
