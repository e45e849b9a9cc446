"""Optimisation of axis parameters: minimise (or maximise) a result column, every check passing.

Two well-kept optimisers: optuna's TPE sampler (seeded; lists as categorical choices, ranges as
floats) and scipy's differential evolution (lists as integer indices with ``integrality``). A
variant that fails a check (or is bad input) scores ``PENALTY`` times one plus its shortfall, so
the search is steered back toward passing variants. Every evaluated variant is a row of the table.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from drivetrain.errors import InputError
from drivetrain.study.record import CHECK_NAMES, dynamics_columns
from drivetrain.study.spec import DYNAMICS_GROUP, OBJECTIVES, RECORD_GROUPS, Study

if TYPE_CHECKING:
    import pandas as pd

PENALTY = 1e12
"""Score of a failing variant (times 1 + its worst shortfall), far above any real objective."""


def objective_column(study: Study) -> tuple[str, str]:
    """(result column, 'minimize' or 'maximize') of the study's objective."""
    opt = study.spec.optimize
    assert opt is not None
    col, direction = OBJECTIVES.get(opt.objective, (opt.objective, "minimize"))
    return col, opt.direction or direction


def optimize(study: Study, progress: bool = False) -> tuple[pd.DataFrame, dict[str, Any]]:
    """Run the study's optimisation; returns every evaluated variant and the best one.

    The best is a mapping: ``parameters`` (in the study's units), ``objective``, ``value`` and
    ``result``, the full ``drivetrain.size`` JSON of that variant.
    """
    from dataclasses import replace

    from drivetrain.axis.model import parse_axis
    from drivetrain.study.batch import full_result
    from drivetrain.study.runner import _Progress, frame, make_plan, run_batch

    opt = study.spec.optimize
    assert opt is not None
    col, direction = objective_column(study)
    dyn = [DYNAMICS_GROUP] if col in dynamics_columns(None) else []  # a dynamic figure as the objective
    record = list(dict.fromkeys([*RECORD_GROUPS, *dyn, *study.spec.record,
                                 *([] if col in _GROUP_COLUMNS else [col])]))
    plan = replace(make_plan(replace(study, spec=study.spec.model_copy(update={"record": record}))))
    rows: list[dict[str, Any]] = []
    bar = _Progress(opt.trials, 0, progress, f"{study.spec.name} ({opt.method})")
    sign = 1.0 if direction == "minimize" else -1.0

    def score(values: tuple[Any, ...]) -> float:
        row = run_batch(plan, [(len(rows), values)])[0]
        rows.append(row)
        bar.advance(1)
        v = row.get(col)
        value = float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else math.nan
        if row.get("ok") and math.isfinite(value):
            return sign * value
        worst = row.get("worst_margin")
        short = -float(worst) if isinstance(worst, float) and math.isfinite(worst) and worst < 0 else 1.0
        return PENALTY * (1.0 + short)

    try:
        if opt.method == "optuna":
            _optuna(study, score, opt.trials)
        else:
            _differential_evolution(study, score, opt.trials)
    finally:
        bar.close()
    table = frame(rows, study)
    ok = table[table["ok"].astype(bool)] if len(table) else table
    if col not in table.columns:
        raise InputError("optimize.objective", "is not a column of the result table", opt.objective)
    values = np.asarray(ok[col], dtype=float) if len(ok) else np.empty(0)
    if not len(values) or not np.any(np.isfinite(values)):
        raise InputError("optimize", f"no evaluated variant passes every check ({len(table)} tried): widen the "
                         "parameter ranges or relax the margins", has_value=False)
    k = int(np.nanargmin(sign * values))
    best_row = ok.iloc[k]
    params = {p.path: _plain(best_row[p.path]) for p in study.parameters}
    result = full_result(parse_axis(plan.axis_dict(tuple(params.values()))), study.spec.points)
    best = {"objective": col, "direction": direction, "value": float(best_row[col]), "parameters": params,
            "variant": int(best_row["variant"]), "result": result}
    table.attrs["drivetrain"]["best"] = {k: v for k, v in best.items() if k != "result"}
    return table, best


_GROUP_COLUMNS = {"rated_power_W", "energy_per_cycle_J", "worst_margin", "rms_torque_Nm", "peak_torque_Nm",
                  "load_rms_torque_Nm", "load_peak_torque_Nm", "ratio",
                  *(f"margin_{n}" for n in CHECK_NAMES), *dynamics_columns(None)}


def _plain(v: Any) -> Any:
    return v.item() if isinstance(v, np.generic) else v


def _optuna(study: Study, score: Any, trials: int) -> None:
    import optuna

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    sampler = optuna.samplers.TPESampler(seed=study.spec.seed)
    opt_study = optuna.create_study(direction="minimize", sampler=sampler)

    def objective(trial: Any) -> float:
        values = []
        for p in study.parameters:
            if p.values is not None:
                values.append(trial.suggest_categorical(p.path, list(p.values)))
            else:
                values.append(trial.suggest_float(p.path, float(p.low), float(p.high)))  # type: ignore[arg-type]
        return float(score(tuple(values)))

    opt_study.optimize(objective, n_trials=trials)


def _differential_evolution(study: Study, score: Any, trials: int) -> None:
    from scipy.optimize import differential_evolution

    bounds, integral = [], []
    for p in study.parameters:
        if p.values is not None:
            bounds.append((0.0, float(len(p.values) - 1)))
            integral.append(True)
        else:
            bounds.append((float(p.low), float(p.high)))  # type: ignore[arg-type]
            integral.append(False)
    popsize = 8
    n_pop = popsize * len(bounds)
    maxiter = max(1, trials // n_pop - 1)  # (maxiter + 1) x popsize x parameters evaluations
    seen: dict[tuple[Any, ...], float] = {}

    def f(x: np.ndarray) -> float:
        values = tuple(p.values[round(float(v))] if p.values is not None else float(v)
                       for p, v in zip(study.parameters, x, strict=True))
        if values not in seen:
            seen[values] = score(values)
        return seen[values]

    differential_evolution(f, bounds, integrality=np.array(integral), seed=study.spec.seed, popsize=popsize,
                           maxiter=maxiter, polish=False, tol=0.0, updating="immediate")


__all__ = ["PENALTY", "objective_column", "optimize"]
