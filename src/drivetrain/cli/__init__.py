"""Command line: ``drivetrain size AXIS``, ``drivetrain catalog ...``, ``drivetrain modes AXIS`` ...

No physics here: each command calls the library and formats its result. Bad input prints one
line naming the field and exits with status 2, without a traceback; ``size``, ``select`` and ``machine size``
print the verdict last (``PASS``, ``PASS WITH UNKNOWNS: ...``, ``FAIL: ...``) and exit 0 when the answer passes,
with or without unknowns (``motor.select.unknown: flag``), and 1 when it fails (under ``unknown: fail`` a check
that cannot be judged fails it; docs/checks.md, "The verdict"). Heavy modules are imported inside the handlers
so ``drivetrain --help`` stays fast.

The package: this module parses the command line and maps errors to exit codes; ``commands`` runs
each sub-command and writes its files; ``sizing`` prints the tables of a sizing result (``size``,
``select``) and ``analyses`` those of ``modes``, ``simulate`` and ``machine size``.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Sequence
from typing import Any

from drivetrain.cli import commands
from drivetrain.cli.commands import EXIT_INPUT
from drivetrain.units import UNIT_CHOICES

__all__ = ["build_parser", "main"]


UNITS_HELP = ("units of the tables (and of the report): si (N*m, kg*cm^2, mm), imperial (lbf*in, lb*in^2, in, "
              "lbf), or as-given (those of the axis file); shaft speeds stay rpm, power W, energy J")


CORE_COMMANDS = ("size", "select", "modes", "simulate", "machine")
"""Sub-commands defined here; the others live with their subsystem (catalog, serve, sweep ...)."""


def build_parser(optional: bool = True) -> argparse.ArgumentParser:
    """The argument parser with every sub-command (``optional=False``: only ``CORE_COMMANDS``, so a
    ``size`` does not import the study, web and catalog command modules to build its parser)."""
    parser = _Parser(prog="drivetrain", description="Size and analyse servo axes.")
    parser.add_argument("--version", action="store_true", help="print the version and exit")
    parser.add_argument("--catalog", dest="user_catalog", metavar="FILE.sqlite",
                        help="your catalog file, e.g. one a team shares (default: $DRIVETRAIN_CATALOG, else "
                             "user.sqlite in the data folder); the shipped data is read beside it")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

    p = sub.add_parser("size", help="duty cycle at the motor shaft, motor checks and selection")
    p.add_argument("axis", help="axis file (YAML)")
    p.add_argument("--json", action="store_true", help="print only the JSON result on standard output")
    p.add_argument("--csv", metavar="FILE", help="write the sampled time series to FILE")
    p.add_argument("--report", metavar="FILE", help="write an HTML (.html) or PDF (.pdf) report")
    p.add_argument("--units", choices=UNIT_CHOICES, default="si", help=UNITS_HELP)
    p.add_argument("--explain", metavar="MODEL", help="say why a catalog motor was accepted or rejected")
    p.add_argument("--points", type=int, default=64, help="samples per profile phase (default 64)")
    p.add_argument("--all", action="store_true",
                   help="list every passing motor-gearbox pair, not only the best configuration of each motor")
    p.add_argument("--aas", metavar="FILE", help="write an IDTA 02021 sizing submodel (AAS JSON) to FILE")
    p.add_argument("--bom", metavar="FILE.csv", help="write the order sheet (one row per part) to FILE.csv")
    p.set_defaults(handler=commands.size)

    p = sub.add_parser("select", help="same as size, with a catalog selection even if the axis names a motor")
    p.add_argument("axis", help="axis file (YAML); a motor it names gives way to a catalog selection (its margins "
                                "and supply voltage kept)")
    p.add_argument("--json", action="store_true", help="print only the JSON result on standard output")
    p.add_argument("--top", type=int, default=None, metavar="N",
                   help="motors listed, each in its best configuration, 1 to 1000 (default: the axis file's "
                        "motor.select.top, else 10)")
    p.add_argument("--units", choices=UNIT_CHOICES, default="si", help=UNITS_HELP)
    p.add_argument("--bom", metavar="FILE.csv", help="write the order sheet (one row per part) to FILE.csv")
    p.set_defaults(handler=commands.select)

    p = sub.add_parser("modes", help="natural frequencies, two-mass resonance and critical speeds of the axis")
    p.add_argument("axis")
    p.add_argument("--json", action="store_true", help="print only the JSON on standard output")
    p.add_argument("--units", choices=UNIT_CHOICES, default="si", help=UNITS_HELP)
    p.set_defaults(handler=commands.modes)

    p = sub.add_parser("simulate", help="closed-loop nonlinear simulation of the axis on its own profile")
    p.add_argument("axis")
    p.add_argument("--json", action="store_true", help="print only the JSON on standard output")
    p.add_argument("--csv", metavar="FILE", help="write the simulated time series to FILE")
    p.add_argument("--plot", metavar="FILE", help="write a figure (PNG, PDF or SVG) to FILE")
    p.add_argument("--cycles", type=int, default=None, help="profile repetitions (default: dynamics.cycles or 1)")
    p.add_argument("--bandwidth", type=float, default=None, help="velocity-loop bandwidth [Hz] (default: tuned)")
    p.add_argument("--units", choices=UNIT_CHOICES, default="si", help=UNITS_HELP)
    p.set_defaults(handler=commands.simulate)

    p = sub.add_parser("machine", help="machine projects: several axes on shared DC buses, one report and BOM")
    msub = p.add_subparsers(dest="machine_command", metavar="ACTION", required=True)
    q = msub.add_parser("size", help="size every axis, the DC bus(es), braking resistors and supply; BOM")
    q.add_argument("machine", help="machine file (YAML, docs/machine.md)")
    q.add_argument("--json", action="store_true", help="print only the JSON result on standard output")
    q.add_argument("--report", metavar="FILE", help="write an HTML (.html) or PDF (.pdf) machine report")
    q.add_argument("--aas", metavar="FILE", help="write an IDTA 02021 sizing submodel (AAS JSON) to FILE")
    q.add_argument("--samples", type=int, default=500, help="random-phasing samples for free axes (default 500)")
    q.add_argument("--seed", type=int, default=0, help="seed of the random phasing (default 0)")
    q.set_defaults(handler=commands.machine_size)

    if optional:
        _optional_parser(sub, "drivetrain.catalog.cli")
        _optional_parser(sub, "drivetrain.web.cli")
        _optional_parser(sub, "drivetrain.study.cli")
    return parser


class _Parser(argparse.ArgumentParser):
    """argparse's parser whose help formatters are told the width (:func:`_help_width`): argparse makes one
    for every argument added, and one left to find the width imports shutil (with bz2 and lzma) for it,
    4 ms of a ``size``. The sub-parsers are of this class too (``add_subparsers`` makes its parser's own)."""

    def _get_formatter(self) -> argparse.HelpFormatter:
        # every argparse formatter class takes the width (HelpFormatter.__init__); typeshed's protocol names prog only
        return self.formatter_class(prog=self.prog, width=_help_width())  # type: ignore[call-arg]


def _help_width() -> int:
    """The width argparse's help formatter takes when not told: ``shutil.get_terminal_size().columns - 2``
    (``COLUMNS`` when a positive number, else the terminal's width, else 80), read as shutil reads it."""
    import os

    try:
        columns = int(os.environ["COLUMNS"])
    except (KeyError, ValueError):
        columns = 0
    if columns <= 0:
        out = sys.__stdout__
        try:
            columns = (os.get_terminal_size(out.fileno()).columns if out is not None else 0) or 80
        except (AttributeError, ValueError, OSError):  # closed, detached, or not a terminal
            columns = 80
    return columns - 2


def _command(argv: Sequence[str]) -> str | None:
    """The sub-command named in ``argv`` (the first word that is not an option or --catalog's value)."""
    skip = False
    for word in argv:
        if skip:
            skip = False
        elif word == "--catalog":
            skip = True
        elif not word.startswith("-"):
            return word
    return None


def _asks_help(argv: Sequence[str]) -> bool:
    """Whether the command line asks for help (``-h``/``--help`` before any ``--``): argparse prints it and
    exits while parsing, so nothing of the sizing stack is imported for it."""
    for word in argv:
        if word == "--":
            return False
        if word in ("-h", "--help"):
            return True
    return False


def _optional_parser(sub: Any, module: str) -> None:
    """Register a sub-command group that lives with its subsystem."""
    import importlib

    try:
        mod = importlib.import_module(module)
    except ModuleNotFoundError as exc:
        if exc.name and module.startswith(exc.name):
            return
        raise
    mod.add_parser(sub)


def _own_process() -> None:
    """Start-up settings for a ``drivetrain`` process (never for ``main(argv)`` called inside another program).

    pydantic looks for plugins by reading every installed distribution's entry points (importlib.metadata)
    when it builds the first model; drivetrain uses none, so discovery is off unless the environment sets
    ``PYDANTIC_DISABLE_PLUGINS`` itself; with discovery off, pydantic's loader module (which imports
    importlib.metadata, email and socket whether discovery is on or not) is replaced by one that finds no
    plugin, as pydantic's own does then. numpy's OpenBLAS runs one thread unless the environment says
    otherwise: at import it would start a thread per core, which spins on the other core (about 30 ms of
    CPU and 10 ms of wall time per start on two cores) for matrices of a few rows, where one thread is
    as fast (worker processes parallelise the study and the web app). (The cyclic garbage collector stays
    on: turning it off saves a little more start-up but would let a large answer's reference cycles hold
    their memory to the end.)
    """
    import os

    if "numpy" not in sys.modules and not any(os.environ.get(v) for v in _BLAS_THREADS):
        os.environ["OPENBLAS_NUM_THREADS"] = "1"
    os.environ.setdefault("PYDANTIC_DISABLE_PLUGINS", "__all__")
    if os.environ["PYDANTIC_DISABLE_PLUGINS"] in ("__all__", "1", "true") and _LOADER not in sys.modules:
        import types

        loader = types.ModuleType(_LOADER, "pydantic's plugin loader with plugin discovery turned off")
        loader.get_plugins = lambda: ()  # type: ignore[attr-defined]
        sys.modules[_LOADER] = loader


_LOADER = "pydantic.plugin._loader"
_BLAS_THREADS = ("OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS")
"""What OpenBLAS reads for its thread count, in its order; one set by the user is left as it is."""


def _import_for_sizing() -> None:
    """Import the modules every sizing needs (numpy, pydantic, the axis model, the sizing engine) with the
    cyclic garbage collector paused, then freeze what exists (``gc.freeze``: the modules, classes and
    functions, which live to the end of the process anyway) and turn the collector on again for the
    command itself. The collector would otherwise examine each of these ~55,000 objects twice while
    they are made and again later, for nothing (30-50 ms of a warm ``size``); the few cycles the
    imports leave (about 460 objects, 0.3 MB) are not collected. Only in a ``drivetrain`` process."""
    import gc

    if not gc.isenabled():
        return
    gc.disable()
    try:
        import drivetrain.sizing.pipeline  # noqa: F401
    finally:
        gc.freeze()
        gc.enable()


def _input_of(args: argparse.Namespace) -> str:
    """The input file a command was given (for a message that cannot name a field)."""
    for name in ("axis", "machine", "study", "file"):
        value = getattr(args, name, None)
        if isinstance(value, str):
            from drivetrain.errors import format_value

            return format_value(value)
    return "input"


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point: returns the exit status (0 passes, with or without unknowns; 1 sized but the answer fails;
    2 bad input)."""
    words = sys.argv[1:] if argv is None else list(argv)
    if argv is None:
        _own_process()
        if _command(words) in ("size", "select") and not _asks_help(words):
            _import_for_sizing()
    parser = build_parser(optional=_command(words) not in CORE_COMMANDS)
    args = parser.parse_args(words)
    if args.version:
        from drivetrain.version import __version__

        print(__version__)
        return 0
    handler: Callable[[argparse.Namespace], int] | None = getattr(args, "handler", None)
    if handler is None:
        parser.print_help()
        return EXIT_INPUT
    from drivetrain.errors import InputError

    try:
        if getattr(args, "user_catalog", None):
            from drivetrain.catalog.cli import use_catalog

            use_catalog(args.user_catalog)
        return handler(args)
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_INPUT
    except (OverflowError, FloatingPointError) as exc:
        # the fields bound every value and the ratio chain (docs/limits.md); a product of bounded values
        # that still leaves the float range is bad input too: one line naming the file, no traceback
        print(f"error: {_input_of(args)}: its values overflow a number in the computation ({exc}); "
              "make the largest values of the file smaller", file=sys.stderr)
        return EXIT_INPUT
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0


