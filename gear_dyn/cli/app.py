"""The ``gear-dyn`` command: a thin shell over the gear_dyn API.

Exit codes: 0 success; 2 user mistake (bad scene, flag or value: one line on stderr);
3 solver failure (one line, with the solver's message); 1 anything unexpected (a bug).
``--debug`` shows the traceback.
"""

from __future__ import annotations

import argparse
import importlib
import os
import signal
import sys
import threading
import traceback
import warnings
from collections.abc import Sequence

from gear_dyn.errors import InputError, SolverError

#: subcommand modules, each exposing register(subparsers)
COMMANDS: tuple[str, ...] = (
    "gear_dyn.cli.run",
    "gear_dyn.cli.demo",
    "gear_dyn.cli.stiffness",
    "gear_dyn.cli.bench",
    "gear_dyn.cli.sweep",
    "gear_dyn.cli.tolerance",
    "gear_dyn.cli.response",
    "gear_dyn.cli.bifurcation",
    "gear_dyn.cli.compare",
    "gear_dyn.cli.excitation",
    "gear_dyn.cli.fmu",
    "gear_dyn.cli.cosim",
    "gear_dyn.cli.relief",
    "gear_dyn.cli.contact",
    "gear_dyn.cli.relief_study",
    "gear_dyn.cli.scenes",
)


class _Parser(argparse.ArgumentParser):
    """ArgumentParser whose errors are one line on stderr and exit code 2."""

    def error(self, message: str) -> None:  # type: ignore[override]
        sys.stderr.write(f"gear-dyn: error: {message} (see {self.prog} --help)\n")
        raise SystemExit(2)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every registered subcommand."""
    parser = _Parser(
        prog="gear-dyn",
        description="Dynamics of gear pairs: mesh stiffness from geometry, single-DOF and "
        "torsional models, solvers with error figures, FMU export. Scenes are TOML files "
        "(see README).",
        epilog="exit codes: 0 ok, 2 bad input, 3 solver failure. Add --debug for tracebacks.",
    )
    parser.add_argument("--debug", action="store_true", help="show tracebacks on errors")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    for name in COMMANDS:
        importlib.import_module(name).register(sub)
    return parser


class Terminated(BaseException):
    """SIGTERM received: unwinds like Ctrl-C so staged outputs are cleaned up."""


#: the pid of the process whose ``main`` installed the SIGTERM handler (a stack: ``main`` may be
#: called again inside a command, as tests do)
_MAIN_PID: list[int] = []


def _on_sigterm(signum: int, frame: object) -> None:
    if _MAIN_PID and os.getpid() != _MAIN_PID[-1]:
        # a worker of a sweep's process pool, forked by multiprocessing, inherited this
        # handler: it dies by the signal as it would without gear_dyn
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        os.kill(os.getpid(), signal.SIGTERM)
        return
    raise Terminated()


def limit_blas_threads() -> None:
    """One BLAS thread per process (pool workers inherit it), unless the user chose otherwise.

    gear_dyn's matrices are 2x2..8x8: BLAS worker threads only oversubscribe a busy machine
    (docs/sweep.md); a plain guard, not a measured gain (benchmarks/results/cli.md). Only the
    ``gear-dyn`` command does this (docs/python_api.md), before numpy loads.
    """
    for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(var, "1")


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``gear-dyn``; returns the exit code.

    SIGTERM is turned into a clean exit (code 143) while the command runs, so that the output
    folder being staged is removed and the previous output stays whole.
    """
    if "numpy" not in sys.modules:
        limit_blas_threads()
    args_list = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in args_list
    if debug:  # accepted anywhere on the line, also after the subcommand
        args_list = ["--debug", *[a for a in args_list if a != "--debug"]]
    previous = None
    if threading.current_thread() is threading.main_thread():
        previous = signal.signal(signal.SIGTERM, _on_sigterm)
        _MAIN_PID.append(os.getpid())
    try:
        with warnings.catch_warnings():  # a warning is one line on stderr, as an error is
            warnings.showwarning = _show_warning
            return _main(args_list, debug)
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
            _MAIN_PID.pop()


def _main(args_list: list[str], debug: bool) -> int:
    try:
        args = build_parser().parse_args(args_list)
        return int(args.func(args) or 0)
    except Terminated:
        sys.stderr.write("gear-dyn: terminated (SIGTERM); no partial output was kept\n")
        return 143
    except SystemExit as exc:
        return int(exc.code) if isinstance(exc.code, int) else 2
    except (InputError, SolverError) as exc:
        if debug:
            traceback.print_exc()
        what, code = ("error", 2) if isinstance(exc, InputError) else ("solver failure", 3)
        sys.stderr.write(f"gear-dyn: {what}: {_one_line(exc)}\n")
        return code
    except BrokenPipeError:  # output piped into e.g. `head`
        return 0
    except KeyboardInterrupt:
        sys.stderr.write("gear-dyn: interrupted; no partial output was kept\n")
        return 130
    except Exception as exc:  # a bug: say so, briefly, unless --debug
        if debug:
            traceback.print_exc()
        else:
            sys.stderr.write(
                f"gear-dyn: internal error: {exc.__class__.__name__}: {_one_line(exc)} "
                "(rerun with --debug and report it)\n"
            )
        return 1


def _show_warning(message: Warning | str, category: type[Warning], filename: str, lineno: int,
                  file: object = None, line: str | None = None) -> None:
    sys.stderr.write(f"gear-dyn: warning: {_one_line(message)}\n")


def _one_line(exc: BaseException | str) -> str:
    return " ".join(str(exc).split())
