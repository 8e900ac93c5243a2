"""The ``presag`` command line.

The command line holds no physics: each sub-command parses its arguments, calls the package API,
and prints a readable table or, with ``--json``, one JSON object. Bad input ends the program with a
one-line reason on standard error and exit status 2; a solver that does not converge ends it with
exit status 3.
"""

from __future__ import annotations

import argparse
import signal
import sys
from collections.abc import Sequence

from presag_opt.cli import common, dynamics, line, recommend, report, robust, sensitivity, static, studies, validation


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every sub-command registered."""
    parser = argparse.ArgumentParser(
        prog="presag",
        description="Pre-sag design for simple railway overhead contact lines.",
        epilog=common.GRAMMAR,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {_version()}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for module in COMMAND_MODULES:
        module.register(subparsers)
    for sub in subparsers.choices.values():
        common.add_run_options(sub)
    return parser


def _version() -> str:
    from presag_opt.version import VERSION

    return VERSION


COMMAND_MODULES = [static, recommend, robust, dynamics, studies, validation, report, line, sensitivity]


def _terminated(signum: int, frame: object) -> None:
    raise KeyboardInterrupt


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``presag`` console script.

    SIGTERM ends a command as Ctrl-C does: its worker processes are stopped and it exits with
    :data:`~presag_opt.cli.common.EXIT_INTERRUPTED` (see :mod:`presag_opt.processes`). The command
    runs in its own :class:`~presag_opt.runtime.Runtime` and leaves nothing behind in the process (the
    SIGTERM handler is restored when it returns), so it can be called in-process, as the tests do.

    Parameters
    ----------
    argv : sequence of str, optional
        The arguments after ``presag`` (default: the process's).

    Returns
    -------
    int
        The exit status (0, or one of the ``EXIT_*`` codes of :mod:`presag_opt.cli.common`; 2 for bad
        usage, from argparse).
    """
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version and bad usage: argparse has printed its message
        return exc.code if isinstance(exc.code, int) else 2
    previous = signal.signal(signal.SIGTERM, _terminated)
    try:
        return common.run(args.handler, args)
    finally:
        signal.signal(signal.SIGTERM, previous)


if __name__ == "__main__":
    sys.exit(main())
