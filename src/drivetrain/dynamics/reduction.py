r"""Model reduction for the dynamic selection's simulation: a small inertia held between two stiff
springs, whose mode lies far above the servo loop, is lumped into its neighbours.

Why: the fixed-step kernel's step is set by the chain's highest mode (``kernel_io.default_step``:
step x omega_max <= 0.2). A small part between two springs (a belt's drive pulley between the
gearbox and the belt) makes a mode far above anything the loop acts on (examples/belt_dynamic.yaml:
1.3-1.8 kHz across the stroke against a 27-30 Hz velocity loop and a 248 Hz first mode), and that
mode alone makes the step 7x shorter than the current loop's period. At the loop's frequencies
such a part is rigid against its springs: it sits where their static balance puts it.

The reduction (singular perturbation: the fast state replaced by its quasi-steady value;
Kokotovic, Khalil, O'Reilly, *Singular Perturbation Methods in Control: Analysis and Design*,
Academic Press 1986, ch. 1; for a chain of inertias the same step is Guyan's static condensation
of that degree of freedom, Guyan, "Reduction of stiffness and mass matrices", AIAA Journal 3(2),
1965, p. 380), for inertia J_j between springs k_a (motor side) and k_b (load side):

- as J_j -> 0 both springs carry the same torque: theta_j = a theta_{j-1} + (1 - a) theta_{j+1},
  a = k_a / (k_a + k_b);
- the springs become one in series, k = k_a k_b / (k_a + k_b) [N m/rad];
- J_j is shared by that static shape, a J_j to the motor side and (1 - a) J_j to the load side
  [kg m^2]: the total (rigid-body) inertia is kept exactly;
- the plays add (gap_a + gap_b [rad]); the lossy gears multiply (eta_a eta_b, forward and back);
- the damping from the low-frequency expansion of the series compliance,
  1/(k_a + j w d_a) + 1/(k_b + j w d_b) = 1/k - j w (d_a/k_a^2 + d_b/k_b^2) + O(w^2):
  d = k^2 (d_a / k_a^2 + d_b / k_b^2) [N m s/rad], taken at the mechanism's weakest position where
  k_b follows the load (the kernel holds a spring's damping constant; the linear checks judge that
  position too);
- where k_b is the mechanism's spring that follows the load (``Chain.spring_table``), the table
  becomes k_a k_b(x) / (k_a + k_b(x)).

When (all of): the inertia is interior (not the motor, which carries the encoder, nor the load, whose
position is judged), has no friction nor damping to ground, and sits between gears that do not
self-lock; its mode (the full chain's highest, at the stiffest and the weakest mechanism spring) is
at least ``SEPARATION`` x the tuned velocity bandwidth and above the current-loop bandwidth (the
torque the motor puts in rolls off above it); that mode is damped (``MIN_DAMPING``: a lightly
damped one rings under the impacts of a backlash and the loop's sampled torque, which a lumped model
cannot show); and the reduced chain's other natural frequencies stay within ``MODE_TOLERANCE`` of the
full chain's (the time scales are separated: the error of the singular perturbation in them is
O(epsilon^2), epsilon the ratio of the frequencies). Ellis, *Control System Design Guide*, 4th ed.
(2012), ch. "Compliance and Resonance", rests on the same premise: the loop neither excites nor
sees a resonance far above its bandwidth.

The linear checks (bandwidth, margins, resonance, anti-resonance) keep the full chain; only the
dynamic selection's simulation (``response.candidate_response``) runs the reduced one, at
``reduced_step``. Validation: bench/RESULTS.md, "Dynamic selection", and
``tests/dynamics/test_reduction.py``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from drivetrain.dynamics.chain import Chain

if TYPE_CHECKING:
    from drivetrain.dynamics.control import ServoLoop

SEPARATION = 10.0
"""The lumped mode lies at least this many times above the tuned velocity bandwidth."""
MODE_TOLERANCE = 0.02
"""The largest relative shift of the chain's other natural frequencies the reduction may cause."""
MIN_DAMPING = 0.05
"""The lumped mode's smallest damping ratio (modal, from the chain's own dampers)."""
STEP_FACTOR = 0.05
"""``reduced_step``: step x omega_max of the reduced chain."""


def _lumpable(chain: Chain, j: int) -> bool:
    return (chain.friction[j] is None and float(chain.ground_damping[j]) == 0.0
            and float(chain.back_efficiency[j - 1]) > 0.0 and float(chain.back_efficiency[j]) > 0.0)


def _weakest(chain: Chain, j: int) -> float:
    """The spring to the load side of inertia j at its weakest [N m/rad]."""
    if chain.spring_table is not None and j == chain.n - 2:
        return float(np.min(chain.spring_table[1]))
    return float(chain.stiffness[j])


def lump_inertia(chain: Chain, j: int) -> Chain:
    """The chain with interior inertia ``j`` lumped into its neighbours (module docstring)."""
    if not 0 < j < chain.n - 1:
        raise ValueError(f"only an interior inertia can be lumped, not {j} of {chain.n}")
    ka, kb = float(chain.stiffness[j - 1]), float(chain.stiffness[j])
    a = ka / (ka + kb)
    inertia = np.array(chain.inertia, dtype=float)
    inertia[j - 1] += a * inertia[j]
    inertia[j + 1] += (1.0 - a) * inertia[j]
    kw = _weakest(chain, j)
    k_weak = ka * kw / (ka + kw)
    d = k_weak**2 * (float(chain.damping[j - 1]) / ka**2 + float(chain.damping[j]) / kw**2)

    def merged(values: np.ndarray, value: float) -> np.ndarray:
        out = np.array(values, dtype=float)
        out[j - 1] = value
        return np.delete(out, j)

    table = chain.spring_table
    if table is not None and j == chain.n - 2:  # the mechanism's spring is k_b: its table goes in series
        table = (table[0], ka * table[1] / (ka + table[1]))
    return chain.with_(
        inertia=np.delete(inertia, j),
        stiffness=merged(chain.stiffness, ka * kb / (ka + kb)),
        damping=merged(chain.damping, d),
        backlash=merged(chain.backlash, float(chain.backlash[j - 1] + chain.backlash[j])),
        efficiency=merged(chain.efficiency, float(chain.efficiency[j - 1] * chain.efficiency[j])),
        back_efficiency=merged(chain.back_efficiency,
                               float(chain.back_efficiency[j - 1] * chain.back_efficiency[j])),
        ground_damping=np.delete(np.asarray(chain.ground_damping, dtype=float), j),
        friction=tuple(f for i, f in enumerate(chain.friction) if i != j),
        names=tuple(nm for i, nm in enumerate(chain.names) if i != j),
        spring_table=table,
    )


def _spring_ends(chain: Chain) -> list[float]:
    """The mechanism spring's stiffest and weakest values [N m/rad] (one value without a table)."""
    if chain.spring_table is None:
        return [float(chain.stiffness[-1])]
    k = chain.spring_table[1]
    return [float(np.max(k)), float(np.min(k))]


def _modes(inertia: np.ndarray, stiffness: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Natural frequencies [rad/s] and M-orthonormal mode shapes of a free chain, the rigid-body mode
    left out (K v = w^2 M v as ``linear.modes``, on arrays: no ``Chain`` built for each trial)."""
    n = inertia.size
    k = np.zeros((n, n))
    i = np.arange(n - 1)
    k[i, i] += stiffness
    k[i + 1, i + 1] += stiffness
    k[i, i + 1] -= stiffness
    k[i + 1, i] -= stiffness
    s = 1.0 / np.sqrt(inertia)
    w2, u = np.linalg.eigh(k * s[:, None] * s[None, :])
    return np.sqrt(np.clip(w2[1:], 0.0, None)), u[:, 1:] * s[:, None]


def reduce_for_simulation(chain: Chain, velocity_bandwidth_hz: float, current_bandwidth_hz: float) -> (
        tuple[Chain, tuple[str, ...]]):
    """``chain`` with every inertia lumped whose mode the servo loop does not act on (module
    docstring), the stiffest first, and one line per lumped inertia. Unchanged, with no lines, where
    nothing qualifies.

    velocity_bandwidth_hz: the tuned velocity loop's -3 dB bandwidth [Hz]; current_bandwidth_hz: the
    drive's current-loop bandwidth [Hz].
    """
    floor = 2.0 * math.pi * max(SEPARATION * velocity_bandwidth_hz, current_bandwidth_hz)
    notes: list[str] = []
    while chain.n >= 3 and math.isfinite(floor):
        inner = [j for j in range(1, chain.n - 1) if _lumpable(chain, j)]
        if not inner:
            break
        # the inertia whose own mode (neighbours held) is highest at the weakest spring
        j = max(inner, key=lambda i: (float(chain.stiffness[i - 1]) + _weakest(chain, i)) / float(chain.inertia[i]))
        reduced = lump_inertia(chain, j)
        damping = chain.damping_matrix()
        w_fast, zeta = math.inf, math.inf
        for k_full, k_red in zip(_spring_ends(chain), _spring_ends(reduced), strict=True):
            w, shapes = _modes(chain.inertia, np.r_[chain.stiffness[:-1], k_full])
            kept, _ = _modes(reduced.inertia, np.r_[reduced.stiffness[:-1], k_red])
            phi = shapes[:, -1]  # M-normalised: modal damping ratio = phi' C phi / (2 w)
            w_fast, zeta = min(w_fast, float(w[-1])), min(zeta, float(phi @ damping @ phi) / (2.0 * float(w[-1])))
            if np.any(np.abs(kept - w[:-1]) > MODE_TOLERANCE * w[:-1]):
                return chain, tuple(notes)
        if w_fast < floor or zeta < MIN_DAMPING:
            break
        notes.append(f"{chain.names[j]} lumped into its neighbours: its mode at {w_fast / (2 * math.pi):.0f} Hz "
                     f"(damping {zeta:.2f}) is >= {SEPARATION:g} x the {velocity_bandwidth_hz:.1f} Hz velocity "
                     f"bandwidth and above the {current_bandwidth_hz:g} Hz current loop")
        chain = reduced
    return chain, tuple(notes)


def reduced_step(full: Chain, reduced: Chain, loop: ServoLoop) -> float:
    """The step for ``reduced`` [s]: the largest that divides the current-loop period with step x
    omega_max <= ``STEP_FACTOR`` on the reduced chain (at the stiffest mechanism spring), never
    finer than ``default_step`` of the full chain. Finer than ``default_step``'s 0.2 because the
    settling tail (the load stuck by friction near the window, backlash closing) is what the
    selection judges. Measured on examples/belt_dynamic.yaml's 20 best candidates, settling windows
    of 50, 20 and 10 um, against the full chain at its ``default_step``: the median settling time
    +1.1, +3.6, +4.1 % at 0.05 (+0.7, +2.7, +2.6 % at 0.025; +4.1, +8.9, +10.7 %, worst +42 %, at
    0.2); bench/RESULTS.md, "Dynamic selection"."""
    from drivetrain.dynamics.kernel_io import _omega_max, default_step

    t_c = loop.current_sample_time
    w = _omega_max(reduced)
    h = t_c / math.ceil(t_c * w / STEP_FACTOR) if w > 0 else t_c
    return max(h, default_step(full, loop))
