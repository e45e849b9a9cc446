"""The study report: one self-contained HTML page (plotly.js embedded, no network needed).

Sections: the study and its provenance; the pass rate and the selected motor over two chosen
parameters (``report: {x, y}``, default the first two); the Pareto front over the passing
variants (motor size against energy per cycle, both smaller is better); the probability that each
check fails; for Monte Carlo designs the sensitivity ranking of the parameters (SALib: Sobol indices
for ``saltelli``, Morris mu* for ``morris``, the moment-independent delta and first-order Sobol
estimates for random, lhs and sobol samples); for an optimisation, the best variant and the history.
"""

from __future__ import annotations

import html
import json
import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    import pandas as pd
    from plotly.graph_objects import Figure

    from drivetrain.study import StudyResult
    from drivetrain.study.spec import Study

MAX_LEVELS = 30
"""A parameter with more distinct values than this is binned (by quantiles) on the maps."""
BINS = 8


def _levels(s: pd.Series) -> pd.Series:
    """Map coordinates of a parameter column: its values, or quantile bins labelled by their middle."""
    import pandas as pd

    if s.nunique(dropna=True) <= MAX_LEVELS or not pd.api.types.is_numeric_dtype(s):
        return s
    cut = pd.qcut(s, BINS, duplicates="drop")
    return cut.map(lambda iv: float(f"{(iv.left + iv.right) / 2:.4g}")).astype(float)


def pass_rate_map(df: pd.DataFrame, x: str, y: str) -> Figure:
    """Heat map of the fraction of variants passing every check, per (x, y) cell."""
    import plotly.graph_objects as go

    g = df.assign(_x=_levels(df[x]), _y=_levels(df[y])).groupby(["_y", "_x"], observed=True)["ok"].mean()
    table = g.unstack("_x")
    fig = go.Figure(go.Heatmap(z=table.to_numpy(dtype=float), x=[str(c) for c in table.columns],
                               y=[str(i) for i in table.index], zmin=0, zmax=1, colorscale="RdYlGn",
                               colorbar={"title": "pass rate"},
                               hovertemplate=f"{x}=%{{x}}<br>{y}=%{{y}}<br>pass rate %{{z:.0%}}<extra></extra>"))
    fig.update_layout(title="Pass rate (every check)", xaxis_title=x, yaxis_title=y, height=460)
    return fig


def motor_map(df: pd.DataFrame, x: str, y: str) -> Figure | None:
    """Heat map of the motor selected most often per (x, y) cell (text: its id)."""
    import plotly.graph_objects as go

    if "motor" not in df or df["motor"].isna().all():
        return None
    d = df.assign(_x=_levels(df[x]), _y=_levels(df[y]))
    d = d[d["ok"].astype(bool)]
    if not len(d):
        return None
    mode = d.groupby(["_y", "_x"], observed=True)["motor"].agg(lambda s: s.value_counts().index[0]).unstack("_x")
    names = sorted({str(v) for v in mode.to_numpy().ravel() if isinstance(v, str)})
    code = {n: k for k, n in enumerate(names)}
    z = np.array([[code.get(str(v), np.nan) if isinstance(v, str) else np.nan for v in row]
                  for row in mode.to_numpy()], dtype=float)
    text = [[str(v) if isinstance(v, str) else "" for v in row] for row in mode.to_numpy()]
    fig = go.Figure(go.Heatmap(z=z, x=[str(c) for c in mode.columns], y=[str(i) for i in mode.index], text=text,
                               texttemplate="%{text}", colorscale="Viridis", showscale=False,
                               hovertemplate=f"{x}=%{{x}}<br>{y}=%{{y}}<br>%{{text}}<extra></extra>"))
    fig.update_layout(title="Selected motor (most frequent per cell, passing variants)", xaxis_title=x,
                      yaxis_title=y, height=460)
    return fig


def pareto_front(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Indices of the points not dominated when both ``a`` and ``b`` are to be small (ties kept once)."""
    order = np.lexsort((b, a))
    keep = []
    best = math.inf
    for k in order:
        if b[k] < best:
            keep.append(k)
            best = b[k]
    return np.asarray(keep, dtype=np.intp)


def pareto_figure(df: pd.DataFrame, names: list[str]) -> Figure | None:
    """Passing variants on (motor size, energy per cycle) with the Pareto front."""
    import plotly.graph_objects as go

    a_col, b_col = "rated_power_W", "energy_per_cycle_J"
    if a_col not in df or b_col not in df:
        return None
    d = df[df["ok"].astype(bool)].dropna(subset=[a_col, b_col])
    if not len(d):
        return None
    a, b = d[a_col].to_numpy(float), d[b_col].to_numpy(float)
    front = pareto_front(a, b)
    hover = ["<br>".join(f"{n} = {r[n]}" for n in names) + f"<br>{r.get('motor', '')}" for _, r in d.iterrows()]
    fig = go.Figure()
    fig.add_trace(go.Scattergl(x=a, y=b, mode="markers", name="passing variants", text=hover,
                               marker={"size": 5, "color": "#9fb7d0"}, hovertemplate="%{text}<extra></extra>"))
    fig.add_trace(go.Scatter(x=a[front], y=b[front], mode="lines+markers", name="Pareto front",
                             text=[hover[k] for k in front], marker={"size": 8, "color": "#c55a11"},
                             hovertemplate="%{text}<extra></extra>"))
    fig.update_layout(title="Pareto front: motor size against energy per cycle", xaxis_title="rated power [W]",
                      yaxis_title="energy per cycle [J]", height=460)
    return fig


def check_failures(df: pd.DataFrame) -> dict[str, float]:
    """Probability that each check fails over the variants (those where the check applies)."""
    out: dict[str, float] = {}
    for c in df.columns:
        if c.startswith("ok_"):
            s = df[c].dropna()
            if len(s):
                out[c[3:]] = float(1.0 - s.astype(bool).mean())
    if "ok" in df and len(df):
        out["any check"] = float(1.0 - df["ok"].astype(bool).mean())
    return out


def sensitivity(study: Study, df: pd.DataFrame, output: str) -> dict[str, Any] | None:
    """Sensitivity ranking of the parameters for ``output`` (SALib), or None for a grid / a missing output."""
    if study.spec.design == "grid" or study.spec.optimize is not None or output not in df:
        return None
    y_all = np.full(study.n_variants(), np.nan)
    y_all[df["variant"].to_numpy(int)] = np.asarray(df[output], dtype=float)
    missing = int(np.count_nonzero(~np.isfinite(y_all)))
    if missing == len(y_all):
        return None
    y = np.where(np.isfinite(y_all), y_all, np.nanmean(y_all))  # a failed variant counts as the mean
    problem = study.salib_problem()
    design = study.spec.design
    if design == "saltelli":
        from SALib.analyze import sobol

        r = sobol.analyze(problem, y, calc_second_order=False, seed=study.spec.seed)
        idx = {"S1": r["S1"], "ST": r["ST"]}
        method, key = "Sobol indices (Saltelli design)", "ST"
    elif design == "morris":
        from SALib.analyze import morris

        r = morris.analyze(problem, study.unit_cube(), y, num_levels=4, seed=study.spec.seed)
        idx = {"mu_star": r["mu_star"], "sigma": r["sigma"]}
        method, key = "Morris elementary effects", "mu_star"
    else:
        from SALib.analyze import delta

        r = delta.analyze(problem, study.unit_cube(), y, seed=study.spec.seed, num_resamples=50)
        idx = {"delta": r["delta"], "S1": r["S1"]}
        method, key = "moment-independent delta and first-order Sobol (Plischke's estimator)", "delta"
    names = study.names
    rows: list[dict[str, Any]] = [{"parameter": n, **{k: float(v[j]) for k, v in idx.items()}}
                                  for j, n in enumerate(names)]
    rows.sort(key=lambda d: -float(d[key]) if math.isfinite(float(d[key])) else math.inf)
    return {"method": method, "output": output, "rank_by": key, "rows": rows, "failed_variants": missing}


def _bar(labels: list[str], values: list[float], title: str, xaxis: str) -> Figure:
    import plotly.graph_objects as go

    fig = go.Figure(go.Bar(x=values, y=labels, orientation="h", marker={"color": "#1f4e79"}))
    fig.update_layout(title=title, xaxis_title=xaxis, height=120 + 32 * len(labels),
                      yaxis={"autorange": "reversed"})
    if values and all(0.0 <= v <= 1.0 for v in values) and xaxis.startswith("fraction"):
        fig.update_xaxes(range=[0.0, 1.0])
    return fig


def render(result: StudyResult) -> str:
    """The report page."""
    import plotly.offline

    from drivetrain.study.optimize import objective_column

    study, df = result.study, result.table
    meta = df.attrs.get("drivetrain", {})
    names = study.names
    numeric = [n for n in names if n in df and _is_numeric(df[n])] or names
    x = study.spec.report.x or (numeric[0] if numeric else names[0])
    y = study.spec.report.y or (numeric[1] if len(numeric) > 1 else (names[1] if len(names) > 1 else x))
    figs: list[tuple[str, Figure]] = []
    sections: list[str] = []
    e = html.escape
    n_ok = int(df["ok"].astype(bool).sum()) if "ok" in df else 0
    units = meta.get("units", {})
    head = [f"<h1>{e(study.spec.name)}</h1>",
            f"<p>{len(df):,} variants ({e(study.spec.design)} design, seed {study.spec.seed}), {n_ok:,} pass every "
            f"check. drivetrain {e(str(meta.get('drivetrain_version')))}, catalog data "
            f"{e(str(meta.get('catalog_data_version')))}.</p>",
            "<table><tr><th>parameter</th><th>unit</th><th>values</th></tr>" +
            "".join(f"<tr><td>{e(n)}</td><td>{e(str(units.get(n) or ''))}</td><td>{e(_describe(df, n))}</td></tr>"
                    for n in names) + "</table>"]
    sections.append("".join(head))
    if "error" in df and (df["error"].astype(str) != "").any():
        bad = df[df["error"].astype(str) != ""]
        sections.append(f"<p>{len(bad)} variants are not valid axes (first: {e(str(bad['error'].iloc[0]))}).</p>")
    if result.best is not None:
        b = result.best
        col, direction = objective_column(study)
        sel = b["result"].get("selection", {}).get("selected") or {}
        sections.append("<h2>Optimum</h2><p>" + e(f"{direction} {col}: {b['value']:.6g} at ") +
                        e(", ".join(f"{k} = {v}" for k, v in b["parameters"].items())) +
                        (e(f"; selected {sel.get('motor')}" + (f" + {sel['gearbox']}" if sel.get("gearbox") else ""))
                         if sel else "") + "</p>")
        import plotly.graph_objects as go

        ok = df["ok"].astype(bool)
        fig = go.Figure(go.Scatter(x=df["variant"][ok], y=df[col][ok], mode="markers", name="passing"))
        fig.update_layout(title=f"{col} of every passing trial", xaxis_title="trial", yaxis_title=col, height=380)
        figs.append(("history", fig))
    if x != y and x in df and y in df:
        figs.append(("pass_rate", pass_rate_map(df, x, y)))
        m = motor_map(df, x, y)
        if m is not None:
            figs.append(("motor_map", m))
    p = pareto_figure(df, names)
    if p is not None:
        figs.append(("pareto", p))
    fails = check_failures(df)
    if fails:
        figs.append(("failures", _bar(list(fails), [v for v in fails.values()], "Probability that each check fails",
                                      "fraction of variants")))
    sens = sensitivity(study, df, study.spec.report.output)
    if sens is not None:
        key = sens["rank_by"]
        figs.append(("sensitivity", _bar([r["parameter"] for r in sens["rows"]], [r[key] for r in sens["rows"]],
                                         f"Sensitivity of {sens['output']}: {sens['method']}", key)))
        cols = [k for k in sens["rows"][0] if k != "parameter"]
        sections.append("<h2>Sensitivity ranking</h2><table><tr><th>parameter</th>" +
                        "".join(f"<th>{e(c)}</th>" for c in cols) + "</tr>" +
                        "".join("<tr><td>" + e(r["parameter"]) + "</td>" +
                                "".join(f"<td>{r[c]:.3g}</td>" for c in cols) + "</tr>" for r in sens["rows"]) +
                        "</table>" + (f"<p>{sens['failed_variants']} variants without a value count as the mean.</p>"
                                      if sens["failed_variants"] else ""))
    divs = "".join(f'<div class="plot" id="study-{k}"></div>' for k, _ in figs)
    calls = ",".join(f'["study-{k}",' + f.to_json().replace("</", "<\\/") + "]" for k, f in figs)
    script = (f'<script type="text/javascript">{plotly.offline.get_plotlyjs()}</script>\n'
              '<script type="text/javascript">(function(){var figs=[' + calls + '];'
              'figs.forEach(function(f){Plotly.newPlot(f[0],f[1].data,f[1].layout,{responsive:true,'
              'displaylogo:false});});})();</script>')
    study_text = f"<h2>Study file</h2><pre>{e(study.text)}</pre>"
    return ("<!DOCTYPE html><html><head><meta charset='utf-8'><title>" + e(study.spec.name) + "</title><style>"
            "body{font-family:system-ui,sans-serif;margin:2em;max-width:1100px}table{border-collapse:collapse}"
            "td,th{border:1px solid #ccc;padding:3px 8px;text-align:left}.plot{margin:1.5em 0}pre{background:#f4f4f4;"
            "padding:1em}</style></head><body>" + "".join(sections) + divs + study_text + script +
            "<script type='application/json' id='study-data'>" +
            json.dumps({"failures": fails, "sensitivity": sens}).replace("</", "<\\/") + "</script></body></html>")


def _is_numeric(s: pd.Series) -> bool:
    import pandas as pd

    return bool(pd.api.types.is_numeric_dtype(s)) and not pd.api.types.is_bool_dtype(s)


def _describe(df: pd.DataFrame, name: str) -> str:
    s = df[name]
    if _is_numeric(s) and len(s):
        return f"{s.min():.4g} to {s.max():.4g} ({s.nunique()} distinct)"
    return ", ".join(str(v) for v in s.unique()[:8])


def write_report(result: StudyResult, path: Path) -> Path:
    """Write the report atomically; returns its path."""
    from drivetrain.files import write_atomic
    from drivetrain.study.runner import _write_text

    text = render(result)
    write_atomic(path, lambda tmp: _write_text(tmp, text))
    return path


__all__ = ["check_failures", "pareto_front", "render", "sensitivity", "write_report"]
