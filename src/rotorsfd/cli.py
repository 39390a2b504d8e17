"""Command-line interface: parse, call :mod:`rotorsfd.api`, print. No physics here.

Exit status: 0 success; 2 bad input (config, ``--set``, arguments, an output folder that
cannot be written: one line naming the field, before any work); 1 any other rotorsfd error
(numerical failure) or a file that cannot be written (one line); 130 interrupted (the
output folder keeps ``INCOMPLETE.txt``); 141 stdout closed early (``| head``), silently.
``--debug`` adds the traceback. Every error line starts with ``rotorsfd: error: ``.

Adding a command: register a function with :func:`command`; the registry builds the
parser, loads the config (``CONFIG`` and ``--set`` when ``config=True``), adds ``-o DIR``
(``output=True``) and ``--quiet`` (``quiet=True``), and handles errors::

    @command("response", "periodic response by harmonic balance", output=True, quiet=True,
             arguments=[arg("--harmonics", type=int, help="override H")])
    def _response(args: argparse.Namespace, config: Config) -> int:
        result = api.run_response(config, progress=not args.quiet)
        result.write(args.output)
        return 0

A name with a space (``"config show"``) is a subcommand of a group (``config``).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import traceback
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from rotorsfd import __version__, cli_args
from rotorsfd.errors import ConfigError, RotorsfdError
from rotorsfd.interrupt import Interrupted, StopRequest

Handler = Callable[[argparse.Namespace, Any], "int | None"]


@dataclass(frozen=True)
class Arg:
    """One extra argparse argument of a command: ``parser.add_argument(*flags, **kwargs)``."""

    flags: tuple[str, ...]
    kwargs: dict[str, Any] = field(default_factory=dict)


def arg(*flags: str, **kwargs: Any) -> Arg:
    """An extra argument of a command (same signature as ``add_argument``)."""
    return Arg(flags, kwargs)


@dataclass(frozen=True)
class Command:
    """A registered subcommand."""

    name: str
    help: str
    handler: Handler
    config: bool = True
    output: bool = False
    quiet: bool = False
    arguments: tuple[Arg, ...] = ()


COMMANDS: dict[str, Command] = {}
GROUPS: dict[str, str] = {"config": "inspect and check configuration files"}


def command(name: str, help: str, *, config: bool = True, output: bool = False,
            quiet: bool = False, arguments: Iterable[Arg] = ()) -> Callable[[Handler], Handler]:
    """Register ``handler(args, config) -> exit status`` as the subcommand ``name``."""

    def register(handler: Handler) -> Handler:
        if name in COMMANDS:
            raise ValueError(f"command {name!r} registered twice")
        COMMANDS[name] = Command(name, help, handler, config, output, quiet, tuple(arguments))
        return handler

    return register


class UsageError(Exception):
    """Bad command-line arguments (exit status 2)."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # type: ignore[override]
        sub = self.prog.removeprefix("rotorsfd").strip()
        where = f"{sub}: " if sub else ""
        raise UsageError(f"{where}{message} (see '{self.prog} --help')")


def _add_common(p: argparse.ArgumentParser, spec: Command) -> None:
    if spec.config:
        p.add_argument("config", metavar="CONFIG", help="TOML configuration file")
        p.add_argument("--set", metavar="KEY=VALUE", action="append", default=[],
                       dest="overrides",
                       help="override a config field by its dotted path, e.g. "
                            "--set elements.sfd.clearance_ratio='0.61 %%' (repeatable)")
    if spec.output:
        p.add_argument("-o", "--output", metavar="DIR", required=True, type=Path,
                       help="output folder (created if missing)")
    if spec.quiet:
        p.add_argument("-q", "--quiet", action="store_true", help="no progress or summary")
    p.add_argument("--debug", action="store_true", default=argparse.SUPPRESS,
                   help="show tracebacks")
    for a in spec.arguments:
        p.add_argument(*a.flags, **a.kwargs)


def build_parser() -> argparse.ArgumentParser:
    """The full parser, built from the command registry."""
    parser = _Parser(prog="rotorsfd", description="Nonlinear dynamics of flexible rotors with "
                     "squeeze film dampers on moving bases.")
    parser.add_argument("--version", action="version", version=f"rotorsfd {__version__}")
    parser.add_argument("--debug", action="store_true", help="show tracebacks on errors")
    top = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    groups: dict[str, Any] = {}
    for name, spec in COMMANDS.items():
        head, _, sub = name.partition(" ")
        if sub:
            if head not in groups:
                gp = top.add_parser(head, help=GROUPS.get(head, ""),
                                    description=GROUPS.get(head, ""))
                groups[head] = gp.add_subparsers(dest="subcommand", metavar="SUBCOMMAND",
                                                 required=True)
            p = groups[head].add_parser(sub, help=spec.help, description=spec.help)
        else:
            p = top.add_parser(name, help=spec.help, description=spec.help)
        _add_common(p, spec)
        p.set_defaults(_command=spec)
    return parser


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split("\n"))


BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS",
                         "VECLIB_MAXIMUM_THREADS")


def _single_threaded_blas() -> None:
    """Default the BLAS libraries to one thread (unless the user set them): the matrices
    here are small (hundreds of DOFs), where threaded LAPACK is slower, and on a busy
    machine it can be 10-40 times slower. Effective only before numpy is first imported."""
    for name in BLAS_THREAD_VARIABLES:
        os.environ.setdefault(name, "1")


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; return the exit status."""
    _single_threaded_blas()
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except UsageError as exc:
        print(f"{PREFIX}{_one_line(exc)}", file=sys.stderr)
        return 2
    except SystemExit as exc:  # --help, --version
        return int(exc.code or 0)
    spec: Command = args._command
    debug = bool(getattr(args, "debug", False))
    try:
        config = None
        if spec.config:
            from rotorsfd import api

            config = api.load_config(args.config, args.overrides)
        check_output(getattr(args, "output", None))
        if spec.config and spec.output:
            _print_warnings(config, Path(args.config).parent)
        status = _run_marked(spec, args, config)
        sys.stdout.flush()  # a closed pipe fails here, not at the interpreter's exit
        return status
    except ConfigError as exc:
        return _report(exc, 2, debug)
    except RotorsfdError as exc:
        return _report(exc, 1, debug)
    except Interrupted as exc:
        print(f"rotorsfd: interrupted: {exc.kept}", file=sys.stderr)
        return 130
    except KeyboardInterrupt:
        print("rotorsfd: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # e.g. `rotorsfd config schema | head`: the reader is gone
        _silence_stdout()
        return 141
    except OSError as exc:  # e.g. an output folder that cannot be written
        return _report(exc, 1, debug)
    except Exception as exc:
        return _report(exc, 1, debug, f"internal error ({type(exc).__name__}), please "
                       "report it; run with --debug for the traceback: ")


PREFIX = "rotorsfd: error: "


def _run_marked(spec: Command, args: argparse.Namespace, config: Any) -> int:
    """Run the handler with ``INCOMPLETE.txt`` in its output folder while it runs (kept,
    saying so, if the run is interrupted; left behind if it is killed)."""
    if not spec.output:
        return int(spec.handler(args, config) or 0)
    from rotorsfd.io.marker import MARKER, IncompleteMarker

    marker = IncompleteMarker.start(args.output, spec.name)
    try:
        status = int(spec.handler(args, config) or 0)
    except Interrupted as exc:
        marker.interrupted(exc.kept)
        exc.kept += f"; {args.output / MARKER} marks the folder incomplete"
        raise
    except KeyboardInterrupt:
        marker.interrupted()
        raise Interrupted(f"{args.output / MARKER} marks the folder incomplete") from None
    except BaseException:
        marker.finished()
        raise
    marker.finished()
    return status


def _report(exc: BaseException, status: int, debug: bool, prefix: str = "") -> int:
    if debug:
        traceback.print_exc()
    print(f"{PREFIX}{prefix}{_one_line(exc)}", file=sys.stderr)
    return status


def _silence_stdout() -> None:
    """Point stdout at /dev/null so that the interpreter's final flush does not fail
    again on a closed pipe (exit status 141, as for a process killed by SIGPIPE)."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):  # stdout is not a real file (tests capture it)
        pass
    finally:
        os.close(devnull)


def _print_warnings(config: Any, search_path: Path) -> None:
    """The configuration's plausibility warnings on stderr, before the work starts."""
    from rotorsfd.analyses.checks import config_warnings

    for line in config_warnings(config, search_path):
        print(f"rotorsfd: warning: {line}", file=sys.stderr)


def check_output(folder: Path | None) -> None:
    """ConfigError naming ``-o`` if results cannot be written in ``folder`` (checked after
    the config, before any work)."""
    from rotorsfd.io.atomic import folder_problem

    if folder is not None and (problem := folder_problem(folder)) is not None:
        raise ConfigError("-o", str(folder), problem)


def progress(iterable: Iterable[Any], *, quiet: bool = False, total: int | None = None,
             desc: str = "") -> Iterable[Any]:
    """A tqdm progress bar on stderr (none with ``--quiet``), for long-running commands."""
    from tqdm import tqdm

    return tqdm(iterable, total=total, desc=desc, disable=quiet, file=sys.stderr,
                dynamic_ncols=True)


# ---- commands ----------------------------------------------------------------------------------


def _print_written(result: Any, paths: dict[str, Path], quiet: bool) -> None:
    """Print a result's summary and the files written (nothing when ``quiet``)."""
    if not quiet:
        print(result.summary())
        print("wrote " + ", ".join(str(p) for p in paths.values()))

@command("config show", "print the resolved configuration (SI units, defaults filled in)",
         arguments=[arg("--format", choices=("toml", "json"), default="toml",
                        help="output format (default: toml)")])
def _config_show(args: argparse.Namespace, config: Any) -> int:
    from rotorsfd.io.config import show_config

    sys.stdout.write(show_config(config, args.format))
    return 0


@command("config check", "validate a configuration and build its model")
def _config_check(args: argparse.Namespace, config: Any) -> int:
    from rotorsfd.analyses.checks import config_warnings
    from rotorsfd.io.config import derived_values
    from rotorsfd.model.build import build_model

    build_model(config, Path(args.config).parent)
    notes = "; ".join(f"{k}: {v}" for k, v in derived_values(config).items())
    print(f"{args.config}: ok ({notes})")
    for line in config_warnings(config, Path(args.config).parent):
        print(f"warning: {line}")
    return 0


@command("config schema", "print the JSON schema of configuration files", config=False)
def _config_schema(args: argparse.Namespace, config: Any) -> int:
    from rotorsfd.io.schema import Config

    print(json.dumps(Config.model_json_schema(), indent=2))
    return 0


@command("config fields", "print the reference of every config field: SI unit, default, "
         "allowed values or range (the README's configuration reference)", config=False,
         arguments=[arg("--format", choices=["markdown", "csv", "json"], default="markdown",
                        help="markdown (one table per section; default), csv or json")])
def _config_fields(args: argparse.Namespace, config: Any) -> int:
    from rotorsfd.io.reference import FORMATS

    sys.stdout.write(FORMATS[args.format]())
    return 0


@command("modal", "Campbell diagram and critical speeds of the linear rotor (SFD film "
         "excluded, centring spring included): critical_speeds.csv, campbell.csv, "
         "campbell.png", output=True, quiet=True)
def _modal(args: argparse.Namespace, config: Any) -> int:
    from rotorsfd import api

    result = api.run_modal(config, search_path=Path(args.config).parent,
                           progress=not args.quiet)
    paths = result.write(args.output)
    if not args.quiet:
        print(result.summary())
        if len(result.critical_speeds) < config.analysis.modal.n_critical:
            print(f"note: {len(result.critical_speeds)} of "
                  f"{config.analysis.modal.n_critical} critical speeds found below "
                  f"{config.analysis.modal.critical_speed_max:g} rad/s")
        print("wrote " + ", ".join(str(p) for p in paths.values()))
    return 0


@command("fit-supports", "fit support stiffnesses (dotted paths) so that the lowest "
         "critical speeds meet targets; prints the values and the --set lines (the "
         "paper gives no support stiffnesses)", quiet=True,
         arguments=[arg("--field", action="append", required=True, metavar="PATH",
                        help="a stiffness field, e.g. elements.sfd.centring_stiffness "
                             "(repeatable)"),
                    arg("--target", action="append", required=True, type=cli_args.speed,
                        metavar="SPEED", help="target critical speed, e.g. 811.3 or "
                        "'7747 rpm' (repeatable, in the order of the modes)"),
                    arg("-o", "--output", type=Path, metavar="DIR",
                        help="also write DIR/fit.json")])
def _fit_supports(args: argparse.Namespace, config: Any) -> int:
    from rotorsfd import api

    result = api.run_fit_supports(config, args.field, args.target,
                                  whirl=config.analysis.modal.whirl)
    if args.output is not None:
        result.write(args.output)
    if not args.quiet:
        print(result.summary())
    return 0 if result.fit.exact else 1


@command("response", "periodic response by harmonic balance and arc-length continuation "
         "([analysis.response]): branch.nc, branch.csv, response plots; exit 1 if the "
         "branch stops early (the points so far are written)", output=True, quiet=True,
         arguments=[arg("--multipliers-at", type=cli_args.ratio, default=None, metavar="X",
                        help="multipliers.png at the point nearest this speed ratio "
                             "Omega/Omega_ref (the parameter in SI for a non-speed branch); "
                             "default: the point of largest |mu|max"),
                    arg("--from-orbit", type=Path, metavar="DIR_OR_NC",
                        help="start the branch on the last period of a time-domain orbit "
                             "(rotorsfd simulate output), Newton-corrected at its speed, "
                             "and continue it both ways over the speed range, stopping "
                             "when it closes on itself (an isola)")])
def _response(args: argparse.Namespace, config: Any) -> int:
    from rotorsfd import api

    cli_args.check_exists("--from-orbit", args.from_orbit)
    with StopRequest("the current point") as stop:
        result = api.run_response(config, search_path=Path(args.config).parent,
                                  progress=not args.quiet, from_orbit=args.from_orbit,
                                  callback=stop)
    paths = result.write(args.output, multipliers_at=args.multipliers_at)
    if stop.requested:
        if not args.quiet:  # the branch's own last line would say "stopped by the callback"
            print("\n".join(line for line in result.summary().splitlines()
                            if "stopped by the callback" not in line))
            print("wrote " + ", ".join(str(p) for p in paths.values()))
        raise Interrupted(f"the {result.branch.n_points} points computed before Ctrl-C "
                          f"({_branch_end(result)}) are written to {args.output}")
    if not result.success:
        print(f"{PREFIX}{_one_line(result.message)}", file=sys.stderr)
        return 1
    _print_written(result, paths, args.quiet)
    return 0


def _branch_end(result: Any) -> str:
    """Where an interrupted response branch ends, in the parameter's terms."""
    lam = result.branch.lam
    if result.is_speed:
        return (f"Omega~ = {lam[0] / result.reference_speed:.4g} .. "
                f"{lam[-1] / result.reference_speed:.4g}")
    return f"{result.parameter} = {lam[0]:.6g} .. {lam[-1]:.6g}"


@command("static", "static deflection of the linear rotor under constant base motion "
         "(gyroscopic moment, base acceleration, gravity) over the [analysis.modal] "
         "speeds: static_deflection.csv", output=True, quiet=True)
def _static(args: argparse.Namespace, config: Any) -> int:
    from rotorsfd import api

    result = api.run_static(config, search_path=Path(args.config).parent)
    path = result.write(args.output)
    if not args.quiet:
        print(result.summary())
        print(f"wrote {path}")
    return 0


@command("sweep", "parameter study: a grid over config fields ([analysis.sweep] axes or "
         "--axis), one task per point, in parallel (local cores, or a Dask cluster): "
         "sweep.nc, summary.csv, sweep.json, points/; exit 1 if points are left pending",
         output=True, quiet=True,
         arguments=[arg("--axis", action="append", default=[], metavar="PATH=V1,V2,...",
                        help="grid axis replacing [analysis.sweep] axes (repeatable), e.g. "
                             "--axis 'elements.sfd.clearance_ratio=0.4 %%,0.5 %%'"),
                    arg("--task", metavar="NAME[:K=V,...]",
                        help="task kind: response, simulate, stability-chart, or "
                             "synthetic (tests) (default: analysis.sweep.task)"),
                    arg("--workers", type=cli_args.integer(1), metavar="N",
                        help="local worker processes (default: the available CPUs)"),
                    arg("--scheduler", metavar="tcp://HOST:PORT",
                        help="run on this Dask distributed scheduler"),
                    arg("--resume", action="store_true",
                        help="continue the sweep in DIR: finished points are kept")])
def _sweep(args: argparse.Namespace, config: Any) -> int:
    from rotorsfd.studies import grid_from_axes, run_sweep
    from rotorsfd.studies.grid import parse_axis

    axes = grid_from_axes(config, dict(map(parse_axis, args.axis))) if args.axis else None
    try:
        result = run_sweep(config, axes, args.task, directory=args.output,
                           workers=args.workers, scheduler=args.scheduler,
                           progress=not args.quiet, resume=args.resume,
                           search_path=Path(args.config).parent)
    except KeyboardInterrupt:
        raise Interrupted(f"partial results written to {args.output} (finished points "
                          "kept; continue with --resume)") from None
    if not args.quiet:
        print(result.summary())
        print(f"wrote {args.output / 'sweep.nc'}, {args.output / 'summary.csv'}")
    return 0 if result.complete else 1



@command("simulate", "time integration at one speed ([analysis.simulate]): timeseries.nc, "
         "poincare.csv, summary.json (motion: period-n, quasi-periodic or chaotic, with the "
         "evidence), simulation.png and orbit/phase/poincare/spectrum.png; journal contact: "
         "one line, exit 1, nothing written", output=True, quiet=True,
         arguments=[arg("--speed", type=cli_args.positive_speed, metavar="SPEED",
                        help="rotor speed, e.g. 850 or '8000 rpm' (rad/s if no unit)"),
                    arg("--speed-ratio", type=cli_args.positive_ratio, metavar="X",
                        help="rotor speed / [reference] speed"),
                    arg("--from-hb", action="store_true",
                        help="start on the HB periodic solution at that speed (H from "
                             "[analysis.response]) instead of the displaced state"),
                    arg("--hb-phase", type=cli_args.ratio, default=0.0, metavar="P",
                        help="with --from-hb: start on the HB orbit a fraction P of the "
                             "period later (e.g. 0.5; off the orbit at t = 0 unless it is "
                             "symmetric: a way to find a coexisting attractor)"),
                    arg("--initial-state", type=Path, metavar="DIR_OR_NC",
                        help="start from the final state of a previous run (its output "
                             "directory or timeseries.nc); same speed: continues it"),
                    arg("--record-periods", type=cli_args.integer(1), metavar="N",
                        help="last periods kept in timeseries.nc (default: poincare_periods)"),
                    arg("--lyapunov-periods", type=cli_args.integer(0), metavar="N",
                        help="periods of the Lyapunov run (default: min(100, periods); "
                             "0: none)")])
def _simulate(args: argparse.Namespace, config: Any) -> int:
    from rotorsfd import api

    if args.speed is not None and args.speed_ratio is not None:
        raise ConfigError("--speed/--speed-ratio", (args.speed, args.speed_ratio),
                          "give --speed or --speed-ratio, not both")
    if args.hb_phase and not args.from_hb:
        raise ConfigError("--hb-phase", args.hb_phase, "needs --from-hb")
    cli_args.check_exists("--initial-state", args.initial_state)
    result = api.run_simulation(config, args.speed, speed_ratio=args.speed_ratio,
                                search_path=Path(args.config).parent,
                                from_hb=args.from_hb, hb_phase=args.hb_phase,
                                initial_state=args.initial_state,
                                record_periods=args.record_periods,
                                lyapunov_periods=args.lyapunov_periods,
                                progress=not args.quiet)
    paths = result.write(args.output)
    _print_written(result, paths, args.quiet)
    return 0


@command("bifurcation-diagram", "brute-force bifurcation diagram: the speed swept up then "
         "down over [analysis.bifurcation_diagram], each speed from the previous end state "
         "(a sweep's first speed, and the speed after a failed one, from the HB orbit); "
         "diagram.csv (Poincare points), speeds.csv, diagram.json, diagram.png; exit 1 if "
         "a speed met journal contact (recorded, the sweep goes on)", output=True,
         quiet=True,
         arguments=[arg("--start", choices=("hb", "displaced"), default="hb",
                        help="fresh start of a sweep: 'hb' (the HB periodic solution, "
                             "default) or 'displaced' (every node displaced by "
                             "[analysis.simulate] initial_displacement)"),
                    arg("--from-hb", action="store_true",
                        help="same as --start hb (kept for older scripts)")])
def _bifurcation_diagram(args: argparse.Namespace, config: Any) -> int:
    from rotorsfd import api

    start = "hb" if args.from_hb else args.start
    result = api.run_bifurcation_diagram(config, search_path=Path(args.config).parent,
                                         start_state=start, progress=not args.quiet)
    paths = result.write(args.output)
    for p in result.contacts:
        print(f"{PREFIX}{p.direction} sweep: speed {p.speed:.6g} rad/s failed "
              f"({p.contact}); the sweep went on", file=sys.stderr)
    _print_written(result, paths, args.quiet)
    return 0 if result.success else 1


@command("stability-chart", "stability chart of the linear rotor (film off) under harmonic "
         "base rotation over two parameters ([analysis.stability_chart] x, y, speed): "
         "chart.nc (max |Floquet multiplier|, stable), chart.png", output=True, quiet=True,
         arguments=[arg("--workers", type=cli_args.integer(1), default=1, metavar="N",
                        help="threads over the grid rows (default: 1)")])
def _stability_chart(args: argparse.Namespace, config: Any) -> int:
    from rotorsfd import api

    if args.workers < 1:
        raise ConfigError("--workers", args.workers, "must be >= 1")
    result = api.run_stability_chart(config, workers=args.workers,
                                     search_path=Path(args.config).parent,
                                     progress=not args.quiet)
    paths = result.write(args.output)
    _print_written(result, paths, args.quiet)
    return 0


def _fold_range(config: Any, parameter: str, start: str, stop: str) -> tuple[float, float]:
    """``--from`` and ``--to`` in SI, checked against the kind of ``--parameter``."""
    from rotorsfd.analyses.response import system_parameter
    from rotorsfd.io.schema import resolve_kind
    from rotorsfd.io.units import UnitError, describe, to_si
    from rotorsfd.model.parameters import find_parameter

    try:
        param = system_parameter(parameter)
    except ConfigError as exc:
        raise ConfigError("--parameter", parameter, exc.allowed) from None
    if param == "speed":
        raise ConfigError("--parameter", parameter, "must differ from the speed (the "
                          "saddle-nodes are those of the speed response)")
    path = parameter.strip()
    if path == param:           # a parameter name: its config path for the units
        path = find_parameter(param).path
    try:
        kind = resolve_kind(config, path)
    except KeyError as exc:
        raise ConfigError("--parameter", parameter, exc.args[0]) from None
    values = []
    for option, text in (("--from", start), ("--to", stop)):
        try:
            values.append(to_si(text, kind))
        except UnitError as exc:
            text_exc = str(exc)
            if not text_exc.startswith("expected"):
                text_exc = f"expected {describe(kind)} for {path}; {text_exc}"
            raise ConfigError(option, text, text_exc) from None
    if values[0] == values[1]:
        raise ConfigError("--to", stop, f"must differ from --from ({start!r})")
    return values[0], values[1]


@command("fold-curve", "two-parameter continuation of the saddle-nodes of the speed "
         "response ([analysis.response] speeds and H) in a second parameter: "
         "fold_curve.csv, fold_curve.json, fold_curve.png (Omega~ of the folds and the "
         "unstable width against the parameter; the cusp where the bistability vanishes); "
         "exit 1 if the curve stops early (the points so far are written)",
         output=True, quiet=True,
         arguments=[arg("--parameter", default="base.pitching.value", metavar="PATH",
                        help="second parameter: base.pitching.value (default), "
                             "base.rolling.value, base.yawing.value, unbalance[0].magnitude"),
                    arg("--from", dest="start", required=True, metavar="VALUE",
                        help="start value, e.g. '0 rad/s' (SI if no unit); the speed branch "
                             "there must have a saddle-node"),
                    arg("--to", dest="stop", required=True, metavar="VALUE",
                        help="end value, e.g. '10 rad/s'"),
                    arg("--harmonics", type=cli_args.integer(1), metavar="H", help="override H")])
def _fold_curve(args: argparse.Namespace, config: Any) -> int:
    from rotorsfd import api

    start, stop = _fold_range(config, args.parameter, args.start, args.stop)
    result = api.run_fold_curve(config, args.parameter, start, stop,
                                search_path=Path(args.config).parent,
                                harmonics=args.harmonics)
    paths = result.write(args.output)
    if not result.success:
        print(f"{PREFIX}fold curve stopped early: {_one_line(result.message)}",
              file=sys.stderr)
        return 1
    _print_written(result, paths, args.quiet)
    return 0


@command("paper", "reproduce Zhang et al. 2025: run the paper's case studies, draw every "
         "figure (DIR/fig<N>.png) and write DIR/report.md and a self-contained "
         "DIR/report.html with our numbers beside the paper's; results per case in "
         "DIR/cases/", config=False, output=True, quiet=True,
         arguments=[arg("--figure", action="append", default=[], metavar="N",
                        help="only this figure of the paper (repeatable), e.g. --figure 7"),
                    arg("--quick", action="store_true",
                        help="Figure 7 only (fixed base, Table 1): under a minute"),
                    arg("--workers", type=cli_args.integer(1), metavar="N",
                        help="worker processes (default: the CPUs, at most 2)")])
def _paper(args: argparse.Namespace, config: Any) -> int:
    from rotorsfd import api

    try:
        result = api.run_paper(args.output, args.figure, quick=args.quick,
                               workers=args.workers, progress=not args.quiet)
    except KeyError as exc:
        bad = [f for f in args.figure if f"no figure {f} " in f"{exc.args[0]} "]
        raise ConfigError("--figure", bad[0] if bad else ", ".join(args.figure),
                          exc.args[0]) from None
    if not args.quiet:
        print(result.summary())
        print(f"wrote {result.paths['report.md']}, {result.paths['report.html']}")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
