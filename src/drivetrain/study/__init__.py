"""Design-space studies of an axis: grids, Monte Carlo and optimisation over axis-file parameters.

``drivetrain sweep STUDY.yaml`` and :func:`sweep`: a study file names a base axis file, the
parameters to vary by their path in it (``mechanism.load.mass``, ``profile[0].time``), a design
(grid, random, lhs, sobol, saltelli, morris) and what to record; the variants are sized on every
core (an embedded Dask cluster) or on an existing Dask scheduler, into a table (Parquet and CSV)
and a study report (HTML). An ``optimize:`` block minimises an objective subject to every check
passing. The study-file reference is docs/studies.md.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import pandas as pd

    from drivetrain.study.spec import Study, load_study, parse_study

_SPEC_NAMES = ("Study", "load_study", "parse_study")


def __getattr__(name: str) -> Any:
    """``Study``, ``load_study`` and ``parse_study`` load the study-file model (numpy, pydantic) when first
    used, so that ``drivetrain --help`` (which imports ``drivetrain.study.cli`` for its parser) stays light."""
    if name in _SPEC_NAMES:
        from drivetrain.study import spec

        return getattr(spec, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


@dataclass
class StudyResult:
    """A study's table (one row per variant) and, for an optimisation, its best variant."""

    study: Study
    table: pd.DataFrame
    best: dict[str, Any] | None = None  # optimisation: parameters, objective, and the variant's size() JSON
    files: list[Path] = field(default_factory=list)

    def to_pandas(self) -> pd.DataFrame:
        """The result table: one row per variant (its parameters, ``ok``, ``error`` and the recorded keys, each
        column's unit in its name), the study's metadata in ``attrs``."""
        return self.table

    def report(self, path: str | Path) -> Path:
        """Write the study report (self-contained HTML). The report is looked up by name: it reads the result,
        the result does not know it (docs/architecture.md)."""
        import importlib

        return Path(importlib.import_module("drivetrain.study.report").write_report(self, Path(path)))


def sweep(study: str | Path | Study, *, out: str | Path | None = None, scheduler: str | None = None,
          workers: int | None = None, batch: int = 200, resume: bool = False, yes: bool = False,
          progress: bool = False, report: str | Path | None = None) -> StudyResult:
    """Run a study file (or a parsed :class:`Study`).

    ``workers``: processes of the embedded Dask cluster (default every core; 0 runs in this
    process); ``scheduler``: address of an existing Dask scheduler (or ``$DRIVETRAIN_SCHEDULER``);
    ``out``: write the table (.parquet, .csv, .meta.json); ``resume``: continue ``out``'s partial
    result; ``yes``: allow more than a million variants; ``report``: write the study report.
    A study with an ``optimize:`` block runs the optimisation (in this process) instead.
    """
    from drivetrain.study.spec import Study, load_study

    s = study if isinstance(study, Study) else load_study(study, yes=yes)
    target = None if out is None else Path(out)
    if report is not None and s.spec.optimize is None:
        from drivetrain.study.stream import STREAM_ABOVE

        if s.n_variants() > STREAM_ABOVE:  # its rows are on disk only (drivetrain.study.stream)
            from drivetrain.errors import InputError

            raise InputError("report", f"a study of more than {STREAM_ABOVE:,} variants has no report: read its "
                             "table, or narrow the study", str(report))
    if s.spec.optimize is not None:
        from drivetrain.study.optimize import optimize

        table, best = optimize(s, progress=progress)
        result = StudyResult(s, table, best)
        if target is not None:
            from drivetrain.study.runner import write_results

            result.files = write_results(table, target, s)
    else:
        from drivetrain.study.stream import run

        table = run(s, out=target, scheduler=scheduler, workers=workers, batch=batch, resume=resume,
                    progress=progress)
        result = StudyResult(s, table)
        if target is not None:
            result.files = [target.with_suffix(x) for x in (".parquet", ".csv", ".meta.json")]
    if report is not None:
        result.files.append(result.report(report))
    return result


__all__ = ["Study", "StudyResult", "load_study", "parse_study", "sweep"]
