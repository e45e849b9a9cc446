"""Sizing a machine: every axis, the DC bus(es) over the machine cycle, phasing, and one bill of materials.

``size_machine(file)`` sizes each axis (``machine.axes``), puts each axis's electrical power on a
common periodic grid of the machine cycle at its offset (``physics.dc_bus``), sums the axes of
each DC-bus group, and sends what the bus still receives to the capacitors and the braking
resistor (``physics.regen.regen_cycle``, as for one drive). Axes with ``offset: free`` are
evaluated all in phase (offset 0) and over a seeded Monte Carlo of random offsets (as Rockwell
Motion Analyzer's random phasing of a shared bus does); the figures reported for sizing are
the worst of the stated offsets, all in phase and the random samples' maximum.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from drivetrain.errors import InputError
from drivetrain.machine.axes import AxisPower, axis_power
from drivetrain.machine.model import BusGroup, Machine, load_machine, parse_machine
from drivetrain.physics import dc_bus, regen
from drivetrain.version import __version__

PERCENTILES = (50, 90, 95, 99, 100)
PHASING_KEYS = ("bus_peak_power_W", "bus_rms_power_W", "supply_peak_power_W", "resistor_energy_per_cycle_J",
                "resistor_peak_power_W", "regen_shared_J")


@dataclass
class MachineResult:
    """The sized machine: axes, buses over the cycle, phasing, bill of materials."""

    machine: Machine
    axes: dict[str, AxisPower]
    offsets: dict[str, float]
    grid: np.ndarray
    buses: list[dict[str, Any]]
    totals: dict[str, Any]
    phasing: dict[str, Any] | None
    bom: list[dict[str, Any]]
    traces: dict[str, dict[str, np.ndarray]] = field(default_factory=dict)
    """per bus: ``{axis name: power [W] on the grid, "bus": sum}`` at the stated offsets"""

    @property
    def ok(self) -> bool:
        """Every axis passes and every bus's supply module and resistors (where given) suffice."""
        axes_ok = all(r.ok for a in self.axes.values() for r in a.results)
        return axes_ok and all(b.get("ok", True) for b in self.buses)

    @property
    def status(self) -> str:
        """The machine's verdict, the worst of its axes' (``SizingResult.status``) and its buses':
        ``fail`` where anything fails, else ``pass with unknowns`` where any axis has a check that could not be
        judged, else ``pass``; ``ok == (status != "fail")``."""
        if not self.ok:
            return "fail"
        return "pass with unknowns" if self.unknowns() else "pass"

    def unknowns(self) -> list[dict[str, str]]:
        """Every axis's checks that could not be judged (``SizingResult.unknowns``), each with its axis
        (and motor, where the axis has several)."""
        out: list[dict[str, str]] = []
        for name, ap in self.axes.items():
            for k, r in enumerate(ap.results):
                who = name if len(ap.results) == 1 else f"{name} (motor {k + 1})"
                out += [{"axis": who, **u.to_dict()} for u in r.unknowns]
        return out

    def verdict_line(self) -> str:
        """The machine's verdict in one line, as ``drivetrain machine size`` prints it last."""
        status = self.status
        unknown = [f"{u['axis']}: {u['check']} ({u['decide']})" for u in self.unknowns()]
        if status == "pass":
            return "PASS"
        if status == "pass with unknowns":
            return "PASS WITH UNKNOWNS: " + ", ".join(unknown)
        bad = [f"axis {name}: {r.verdict_line().removeprefix('FAIL: ')}" for name, ap in self.axes.items()
               for r in ap.results if not r.ok]
        bad += [f"bus {b.get('name', '?')}: its supply module or braking resistors do not suffice"
                for b in self.buses if not b.get("ok", True)]
        return "FAIL: " + "; ".join(bad)

    def to_dict(self) -> dict[str, Any]:
        """The JSON result (docs/machine.md)."""
        m = self.machine
        axes = []
        for a in m.axes:
            ap = self.axes[a.name]
            entry: dict[str, Any] = {
                "name": a.name, "source": a.source, "motors": a.motors, "load_shares": list(a.shares),
                "split_basis": a.split_basis, "offset_s": self.offsets[a.name], "phasing": (
                    "free" if a.free else (f"after {a.after}" if a.after else "fixed")),
                "cycle_s": ap.period, "motion_end_s": ap.motion_end, "power_basis": ap.basis, "notes": ap.notes,
                "peak_power_W": float(np.max(ap.power)), "regen_energy_J": float(
                    np.sum(regen.trapezoid_weights(ap.t) * np.maximum(-ap.power, 0.0))),
                "ok": all(r.ok for r in ap.results),
            }
            if a.motors == 1:
                entry["result"] = ap.results[0].to_dict()
            else:
                entry["results"] = [r.to_dict() for r in ap.results]
            axes.append(entry)
        return {"machine": {"name": m.name, "drivetrain_version": __version__, "cycle_time_s": m.cycle_time,
                            "supply_voltage_V": m.supply.voltage, "supply_phases": m.supply.phases,
                            "ok": self.ok, **self.totals},
                "buses": self.buses, "phasing": self.phasing, "axes": axes, "bill_of_materials": self.bom,
                "verdict": {"status": self.status, "unknowns": self.unknowns()}}

    def series(self) -> dict[str, np.ndarray]:
        """The machine cycle's grid and every axis's and bus's power [W] at the stated offsets."""
        cols: dict[str, np.ndarray] = {"t_s": self.grid}
        for bus, tr in self.traces.items():
            for k, v in tr.items():
                cols[f"{bus}:{k}" if k == "bus" else k] = v
        return cols


def _offsets(m: Machine, axes: dict[str, AxisPower], free: dict[str, np.ndarray] | None = None,
             samples: int = 1) -> dict[str, np.ndarray]:
    """Start of every axis [s] (arrays of ``samples``): fixed, free (given or 0), or after another axis."""
    out: dict[str, np.ndarray] = {}

    def of(name: str) -> np.ndarray:
        if name in out:
            return out[name]
        a = m.axis(name)
        if a.after is not None:
            val = of(a.after) + axes[a.after].motion_end + a.delay
        elif a.offset is not None:
            val = np.full(samples, a.offset)
        else:
            val = free[name] if free is not None and name in free else np.zeros(samples)
        out[name] = np.mod(val, m.cycle_time)
        return out[name]

    for a in m.axes:
        of(a.name)
    return out


def _sample(m: Machine, axes: dict[str, AxisPower], names: tuple[str, ...], offs: dict[str, float],
            uniform: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Grid [s], weights [s] and the powers (A, N) [W] of ``names`` at the offsets ``offs`` [s]."""
    t, right, w = dc_bus.periodic_grid([axes[n].t + offs[n] for n in names], m.cycle_time, uniform)
    pw = np.stack([dc_bus.periodic_resample(axes[n].t, axes[n].power, t, offs[n], m.cycle_time, right)
                   for n in names])
    return t, w, pw


def _bus_figures(group: BusGroup, m: Machine, axes: dict[str, AxisPower], t: np.ndarray, powers: np.ndarray,
                 w: np.ndarray) -> dict[str, Any]:
    """Bus, capacitor, resistor and supply figures of one bus trace ``p`` [W] (axes' powers (A, N))."""
    e_c = sum(sum(axes[n].capacitor_energy) for n in group.axes)
    u_dc = max(axes[n].dc_bus_voltage or 0.0 for n in group.axes)
    if group.absorbable_energy is not None:
        e_c += group.absorbable_energy
    elif group.capacitance is not None and group.bus_max_voltage is not None:
        e_c += float(regen.capacitor_energy(group.capacitance, group.bus_max_voltage, u_dc))
    p = powers.sum(axis=0)
    k0 = dc_bus.start_at_rest(p)
    r = regen.regen_cycle(np.roll(t, -k0), np.roll(p, -k0), 0.0, e_c, weights=np.roll(w, -k0), period=m.cycle_time)
    supply = np.maximum(p, 0.0)
    sup_cur = dc_bus.line_current(supply, m.supply.voltage, m.supply.phases, m.supply.power_factor)
    return {
        "bus_peak_power_W": float(p.max()),
        "bus_peak_regen_power_W": float(max(-p.min(), 0.0)),
        "bus_rms_power_W": float(math.sqrt(np.sum(w * p**2) / m.cycle_time)),
        "bus_mean_power_W": float(np.sum(w * p) / m.cycle_time),
        "regen_shared_J": dc_bus.shared_energy(powers, w),
        "regen_into_bus_J": float(np.sum(w * np.maximum(-powers, 0.0))),
        "capacitor_energy_per_event_J": e_c,
        "capacitor_absorbed_J": r.capacitor_absorbed,
        "resistor_energy_per_cycle_J": r.resistor_energy,
        "resistor_peak_power_W": r.resistor_peak_power,
        "resistor_average_power_W": r.resistor_average_power,
        "supply_peak_power_W": float(supply.max()),
        "supply_continuous_power_W": float(np.sum(w * supply) / m.cycle_time),
        "supply_rms_power_W": float(math.sqrt(np.sum(w * supply**2) / m.cycle_time)),
        "supply_peak_current_A": float(sup_cur.max()),
        "supply_rms_current_A": float(math.sqrt(np.sum(w * sup_cur**2) / m.cycle_time)),
        "dc_bus_voltage_V": u_dc,
    }


def _resistor_window(group: BusGroup, axes: dict[str, AxisPower], fig: dict[str, Any]) -> dict[str, Any]:
    """Resistance window and the check of the group's resistors (several in parallel share by 1/R)."""
    mins = [x for n in group.axes for x in axes[n].min_resistance]
    if group.min_resistance is not None:
        mins.append(group.min_resistance)
    ons = [x for n in group.axes for x in axes[n].regen_on_voltage]
    if group.regen_on_voltage is not None:
        ons = [group.regen_on_voltage]
    r_min = max(mins) if mins else None
    r_max = None
    p_peak = fig["resistor_peak_power_W"]
    if ons and p_peak > 0:
        r_max = float(regen.resistor_max_resistance(min(ons), p_peak))
    out: dict[str, Any] = {"resistor_min_ohm": r_min, "resistor_max_ohm": r_max,
                           "resistor_needed": fig["resistor_energy_per_cycle_J"] > 0.0}
    if not group.resistors:
        return out
    units = [(r, 1.0 / r.resistance if r.resistance else math.nan) for r in group.resistors for _ in range(r.quantity)]
    g_sum = sum(g for _, g in units)
    checks = []
    for r, g in units:
        share = g / g_sum if math.isfinite(g_sum) and g_sum > 0 else 1.0 / len(units)
        avg, peak = fig["resistor_average_power_W"] * share, p_peak * share
        checks.append({"id": r.id, "share": share, "average_power_W": avg, "peak_power_W": peak,
                       "continuous_power_W": r.continuous_power, "rated_peak_power_W": r.peak_power,
                       "ok": (r.continuous_power is None or avg <= r.continuous_power)
                       and (r.peak_power is None or peak <= r.peak_power)})
    ok = all(c["ok"] for c in checks)
    if math.isfinite(g_sum) and g_sum > 0:
        r_eq = 1.0 / g_sum
        out["resistor_equivalent_ohm"] = r_eq
        if r_min is not None and r_eq < r_min:
            ok = False
        if r_max is not None and r_eq > r_max:
            ok = False
    out["resistors"] = checks
    out["resistors_ok"] = ok
    return out


def _module_check(group: BusGroup, fig: dict[str, Any]) -> dict[str, Any] | None:
    mod = group.supply_module
    if mod is None:
        return None
    ok = ((mod.continuous_power is None or fig["supply_continuous_power_W"] <= mod.continuous_power)
          and (mod.peak_power is None or fig["supply_peak_power_W"] <= mod.peak_power))
    return {"id": mod.id, "vendor": mod.vendor, "continuous_power_W": mod.continuous_power,
            "peak_power_W": mod.peak_power, "ok": ok}


def size_machine(machine: Machine | dict[str, Any] | str | Path, points_per_phase: int = 64, grid_points: int = 1000,
                 phasing_samples: int = 500, seed: int = 0) -> MachineResult:
    """Size a machine: a ``Machine``, a mapping of the machine file (includes relative to the cwd), or a path."""
    if isinstance(machine, (str, Path)):
        machine = load_machine(machine)
    elif isinstance(machine, dict):
        machine = parse_machine(machine)
    m = machine
    if not 1 <= phasing_samples <= 100_000:
        raise InputError("phasing_samples", "must be between 1 and 100000", phasing_samples)
    axes = {a.name: axis_power(a, points_per_phase, m.supply.voltage) for a in m.axes}
    offs = {k: float(v[0]) for k, v in _offsets(m, axes).items()}
    names = tuple(a.name for a in m.axes)
    grid, w, every = _sample(m, axes, names, offs, grid_points)
    buses: list[dict[str, Any]] = []
    traces: dict[str, dict[str, np.ndarray]] = {}
    total = every.sum(axis=0)
    for g in m.buses:
        pw = every[[names.index(n) for n in g.axes]]
        traces[g.name] = {**{n: pw[i] for i, n in enumerate(g.axes)}, "bus": pw.sum(axis=0)}
        fig = _bus_figures(g, m, axes, grid, pw, w)
        fig.update(_resistor_window(g, axes, fig))
        entry: dict[str, Any] = {"name": g.name, "axes": list(g.axes), "declared": g.declared, **fig}
        mod = _module_check(g, fig)
        if mod is not None:
            entry["supply_module"] = mod
        entry["ok"] = (mod is None or mod["ok"]) and entry.get("resistors_ok", True)
        buses.append(entry)
    phasing = _phasing(m, axes, grid_points, phasing_samples, seed)
    totals = _totals(m, buses, total, w)
    if phasing is not None:
        totals["worst_phasing"] = {k: max(totals.get(k, 0.0), phasing["in_phase"][k], phasing["random"][k]["p100"])
                                   for k in PHASING_KEYS}
    bom = _bom(m, axes, buses)
    return MachineResult(machine=m, axes=axes, offsets=offs, grid=grid,
                         buses=buses, totals=totals, phasing=phasing, bom=bom, traces=traces)


def _totals(m: Machine, buses: list[dict[str, Any]], total: np.ndarray, w: np.ndarray) -> dict[str, Any]:
    """The machine block: the first bus's figures for a one-bus machine; sums (energies, powers) otherwise."""
    if len(buses) == 1:
        b = buses[0]
        return {k: v for k, v in b.items() if k not in ("name", "axes", "declared", "ok")}
    summed = ("regen_shared_J", "regen_into_bus_J", "capacitor_absorbed_J", "resistor_energy_per_cycle_J",
              "resistor_average_power_W", "supply_continuous_power_W")
    out: dict[str, Any] = {k: float(sum(b[k] for b in buses)) for k in summed}
    out["bus_peak_power_W"] = float(total.max())
    out["bus_rms_power_W"] = float(math.sqrt(np.sum(w * total**2) / m.cycle_time))
    out["resistor_peak_power_W"] = float(sum(b["resistor_peak_power_W"] for b in buses))
    out["supply_peak_power_W"] = float(sum(b["supply_peak_power_W"] for b in buses))
    out["supply_peak_current_A"] = float(sum(b["supply_peak_current_A"] for b in buses))
    out["resistor_min_ohm"] = None
    out["resistor_max_ohm"] = None
    out["note"] = ("several DC buses: energies and average powers are sums over the buses; peak powers and currents "
                   "are the sum of each bus's peak (an upper bound); the resistance window is per bus")
    return out


def _phasing(m: Machine, axes: dict[str, AxisPower], uniform: int, samples: int,
             seed: int) -> dict[str, Any] | None:
    """All free axes in phase (offset 0), and a seeded Monte Carlo of uniformly random offsets: percentiles."""
    free = [a.name for a in m.axes if a.free]
    if not free:
        return None
    rng = np.random.default_rng(seed)
    draws = {n: rng.uniform(0.0, m.cycle_time, samples) for n in free}
    offs = _offsets(m, axes, draws, samples)
    zero = _offsets(m, axes)
    stats: dict[str, list[float]] = {k: [] for k in PHASING_KEYS}
    in_phase: dict[str, float] = {k: 0.0 for k in PHASING_KEYS}
    for g in m.buses:
        if not any(n in free or _depends_on_free(m, n) for n in g.axes):
            continue
        t0, w0, base = _sample(m, axes, g.axes, {n: float(zero[n][0]) for n in g.axes}, uniform)
        fig0 = _bus_figures(g, m, axes, t0, base, w0)
        for k in PHASING_KEYS:
            in_phase[k] = max(in_phase[k], fig0[k])
        for s in range(samples):
            ts, ws, pw = _sample(m, axes, g.axes, {n: float(offs[n][s]) for n in g.axes}, uniform)
            fig = _bus_figures(g, m, axes, ts, pw, ws)
            for k in PHASING_KEYS:
                if len(stats[k]) <= s:
                    stats[k].append(fig[k])
                else:
                    stats[k][s] = max(stats[k][s], fig[k])
    random = {k: {f"p{q}": float(np.percentile(v, q)) if v else 0.0 for q in PERCENTILES} for k, v in stats.items()}
    return {"free_axes": free, "samples": samples, "seed": seed, "in_phase": in_phase, "random": random,
            "method": "uniform random offsets of the free axes over the machine cycle (after: chains follow)"}


def _depends_on_free(m: Machine, name: str) -> bool:
    a = m.axis(name)
    while a.after is not None:
        a = m.axis(a.after)
    return a.free


def axis_bom_rows(name: str, results: list[Any]) -> list[dict[str, Any]]:
    """The bill-of-materials rows of one machine axis: each motor's order sheet (``sizing.order``), its rows
    as they are, less the braking resistor (a machine sizes its resistors per DC bus); a row without an order
    code carries its name, status and number of open points as ``note`` (the points in ``open_points``)."""
    from drivetrain.sizing.order import order_sheet

    rows = []
    for res in results:
        for r in order_sheet(res).to_dict()["rows"]:
            if r["part"] == "braking_resistor":
                continue
            n = len(r["open_points"])
            note = None if r["order_code"] else (f"{r['name']} ({r['status']}" + (f", {n} open point{'s' * (n > 1)}"
                                                                                 if n else "") + ")")
            rows.append({"kind": r["part"], "order_code": r["order_code"], "vendor": r["vendor"],
                         "quantity": r["quantity"], "axis": name, "status": r["status"], "catalog_id": r["catalog_id"],
                         "name": r["name"], "spec": r["spec"], "open_points": r["open_points"],
                         **({"note": note} if note else {})})
    return rows


def _resistor_note(spec: dict[str, Any]) -> str:
    """A bus resistor's specification in one line of the BOM."""
    lo, hi = spec["resistance_min_ohm"], spec["resistance_max_ohm"]
    window = (f", {'drive minimum not given' if lo is None else f'{lo:.4g}'} to "
              f"{'(no bus voltage)' if hi is None else f'{hi:.4g}'} ohm")
    values = spec.get("standard_values_ohm")
    return (f"to choose: {spec['average_power_W']:.4g} W average, {spec['peak_power_W']:.4g} W peak, "
            f"{spec['energy_per_cycle_J']:.4g} J per cycle{window}"
            + (f" (E12: {', '.join(f'{v:g}' for v in values)} ohm)" if values else ""))


def _bom(m: Machine, axes: dict[str, AxisPower], buses: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """One bill of materials: each axis's order-sheet rows (``axis_bom_rows``), identical order codes (and
    identical specifications) merged, quantities added, axes listed.

    A bus that needs a braking resistor but names none gets a row without order code saying what
    to choose (energy, average and peak power, resistance window)."""
    rows = [r for a in m.axes for r in axis_bom_rows(a.name, axes[a.name].results)]
    for g, b in zip(m.buses, buses, strict=True):
        if not g.resistors and b["resistor_needed"]:
            from drivetrain.sizing.order_spec import resistor_spec

            spec, open_points = resistor_spec(b["resistor_peak_power_W"], b["resistor_average_power_W"],
                                              b["resistor_energy_per_cycle_J"], None, b.get("resistor_min_ohm"),
                                              b.get("resistor_max_ohm"), None, b.get("dc_bus_voltage_V"))
            rows.append({"kind": "braking_resistor", "order_code": None, "vendor": None, "quantity": 1, "axis": g.name,
                         "status": "specification", "catalog_id": None, "name": "braking resistor of the DC bus",
                         "spec": spec, "open_points": open_points,
                         "note": _resistor_note(spec)})
    for g in m.buses:
        if g.supply_module is not None:
            rows.append({"kind": "supply_module", "order_code": g.supply_module.id, "vendor": g.supply_module.vendor,
                         "quantity": 1, "axis": g.name})
        for res in g.resistors:
            rows.append({"kind": "braking_resistor", "order_code": res.id, "vendor": res.vendor,
                         "quantity": res.quantity, "axis": g.name})
    merged: dict[tuple[str, str | None], dict[str, Any]] = {}
    for r in rows:
        key = (r["kind"], r["order_code"] if r["order_code"] is not None else
               f"note:{r.get('note')}:{sorted(r.get('spec', {}).items())}")
        if key in merged:
            merged[key]["quantity"] += r["quantity"]
            if r["axis"] not in merged[key]["used_by"]:
                merged[key]["used_by"].append(r["axis"])
        else:
            merged[key] = {**{k: v for k, v in r.items() if k != "axis"}, "used_by": [r["axis"]]}
    order = {"motor": 0, "drive": 1, "gearbox": 2, "supply_module": 3, "braking_resistor": 4, "brake": 5,
             "coupling": 6, "screw": 7, "guide": 8}
    return sorted(merged.values(), key=lambda r: (order.get(r["kind"], 9), str(r["order_code"])))
