"""Shared pieces of the command line: running a handler, errors, options, progress, tables, JSON.

Helpers every sub-command uses (the grammar is documented once, in :data:`GRAMMAR`):

- :func:`run` runs a handler inside the command's :class:`~presag_opt.runtime.Runtime` (built from its
  options and the environment): one-line errors, Ctrl-C (exit 130), a closed pipe (exit 141);
- :func:`add_run_options` adds ``--quiet``, ``--progress`` and ``--no-cache`` to a sub-command;
- :func:`progress` gives the one progress display (tqdm on standard error) for long work;
- :func:`band` and :func:`float_list` parse ``LOW:HIGH`` bands and ``A,B,C`` lists;
- :func:`output_folder` checks an output folder (``--out``, ``--plot``) before any work starts;
- :func:`form_find_for` form-finds, saying beforehand when it will take long;
- :func:`model_help` is the help line of a model argument, listing the built-in models;
- :func:`print_warnings` prints the one-line warnings of a result; every warning the package raises
  while a command runs is shown the same way, once, and :func:`print_json` lists them all under
  ``warnings``.
"""

from __future__ import annotations

import argparse
import contextvars
import json
import math
import os
import sys
import tempfile
import threading
import time
import traceback
import warnings
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from presag_opt.errors import ConvergenceError, ModelError, StorageError
from presag_opt.runtime import NO_CACHE_ENV, Runtime

if TYPE_CHECKING:  # casadi is imported by the commands that form-find, not by this module
    from presag_opt.static.discretisation import StaticSettings
    from presag_opt.static.equilibrium import EquilibriumState
    from presag_opt.system.catenary import Catenary

EXIT_BAD_INPUT = 2
EXIT_NOT_CONVERGED = 3
EXIT_INTERRUPTED = 130
"""128 + SIGINT, as a shell reports a program stopped by Ctrl-C."""
EXIT_STORAGE = 4
"""A file could not be written or read: no space left, no permission, a read-only folder."""
EXIT_PARTIAL = 5
"""A long analysis finished without some of its evaluations: they failed (each kept with its inputs
and reason), the result leaves them out and says what that costs, and one line on standard error says
how many (:func:`report_failures`)."""
EXIT_INTERNAL = 70
"""An error the package did not expect (EX_SOFTWARE): one line, the traceback with PRESAG_DEBUG=1."""
EXIT_BROKEN_PIPE = 141
"""128 + SIGPIPE, as a shell reports a program whose reader went away (``presag … | head``)."""

_SHOWN_WARNINGS: contextvars.ContextVar[dict[str, None]] = contextvars.ContextVar("presag_shown_warnings")
"""The warnings shown so far by the running command, in order (each once): a fresh record per
:func:`run`, reset when it returns (outside a command every call of :func:`print_warnings` starts afresh)."""

PROGRESS_DELAY = 2.0
"""Seconds of work before a progress display appears (shorter work shows none). [s]"""

PROGRESS_TICK = 1.0
"""Seconds between redraws of a shown progress display (its elapsed time). [s]"""

GRAMMAR = """\
command-line grammar:
  LOW:HIGH   a band, e.g. --fm-band 70:148 (N), --static-force 70:140 (N)
  A,B,C      a list of values, e.g. --forces 50,100,150 (N)
  units      are in each option's metavar (N, MM, M, KMH, PERCENT); one number for a band means LOW = HIGH
  --quiet / --progress   no progress display / the display at once, even when standard error is not a terminal
  --no-cache             do not read or write the cache of form-found states and of the finished evaluations
                         of long analyses (also: PRESAG_NO_CACHE=1; clear it with `presag cache --clear`)
exit status: 0 done, 2 bad input, 3 a solver did not converge, 4 a file could not be written, 5 done without some
  failed evaluations (a long analysis: one line says how many), 70 an unexpected error, 130 interrupted"""
"""The grammar shared by every sub-command, printed as the epilog of ``presag --help``."""


def run(handler: Callable[[argparse.Namespace], int | None], args: argparse.Namespace) -> int:
    """Run a sub-command handler, turning expected errors into a one-line message and exit code.

    The handler runs inside the command's runtime (:func:`command_runtime`: the form-finding cache
    unless ``--no-cache``, compiled code, error display). Every warning raised while
    the handler runs is printed once as ``presag: warning: …`` (see :func:`print_warnings`). A closed
    standard output (the reader of a pipe went away) ends the program quietly with
    :data:`EXIT_BROKEN_PIPE`; a file that cannot be written (:class:`OSError`) ends it with one line
    and :data:`EXIT_STORAGE`; any other error with one line and :data:`EXIT_INTERNAL` (the traceback
    only with ``PRESAG_DEBUG=1``).

    Parameters
    ----------
    handler : callable
        Sub-command handler taking the parsed options and returning an exit code or None.
    args : argparse.Namespace
        Parsed options of the sub-command.
    """
    shown = _SHOWN_WARNINGS.set({})
    try:
        settings = command_runtime(args)
        with settings, warnings.catch_warnings():
            warnings.simplefilter("default")
            for category in (DeprecationWarning, PendingDeprecationWarning, ImportWarning, ResourceWarning):
                warnings.simplefilter("ignore", category)
            warnings.showwarning = _show_warning
            return _run(handler, args, settings.debug)
    finally:
        _SHOWN_WARNINGS.reset(shown)


def command_runtime(args: argparse.Namespace) -> Runtime:
    """The runtime of a command: the environment's (:meth:`~presag_opt.runtime.Runtime.from_environment`),
    with the form-finding cache in the user's cache folder unless ``--no-cache`` or ``PRESAG_NO_CACHE``."""
    return Runtime.from_environment(state_cache=not getattr(args, "no_cache", False))


def _run(handler: Callable[[argparse.Namespace], int | None], args: argparse.Namespace, debug: bool) -> int:
    try:
        return handler(args) or 0
    except ModelError as exc:
        print(f"presag: error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except ConvergenceError as exc:
        print(f"presag: error: {exc}", file=sys.stderr)
        return EXIT_NOT_CONVERGED
    except KeyboardInterrupt:
        print("presag: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except BrokenPipeError:
        # Python would report the failed flush of stdout at exit; point stdout at /dev/null instead
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_BROKEN_PIPE
    except StorageError as exc:
        print(f"presag: error: {exc}", file=sys.stderr)
        return EXIT_STORAGE
    except OSError as exc:
        print(f"presag: error: {os_error_line(exc)}", file=sys.stderr)
        return EXIT_STORAGE
    except (Exception, MemoryError) as exc:  # noqa: BLE001 - the last line of defence: never a raw traceback
        if debug:
            traceback.print_exc()
        where = traceback.extract_tb(exc.__traceback__)[-1] if exc.__traceback__ else None
        at = f" in {Path(where.filename).name}:{where.lineno}" if where else ""
        print(f"presag: internal error: {type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}{at} "
              "(please report it; PRESAG_DEBUG=1 shows the traceback)", file=sys.stderr)
        return EXIT_INTERNAL


def os_error_line(exc: OSError) -> str:
    """One line for a failed file operation: the file, what went wrong, and what to do."""
    name = f"{exc.filename}: " if exc.filename else ""
    reason = exc.strerror or str(exc)
    hint = {28: "free some space", 13: "check the permissions", 30: "the file system is read-only",
            122: "free some space (disk quota)"}.get(exc.errno or 0)
    return f"{name}{reason}" + (f" ({hint})" if hint else "")


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """``warnings.showwarning`` of a running command: one line, each distinct message once."""
    print_warnings([str(message)])


def add_run_options(parser: argparse.ArgumentParser) -> None:
    """Add ``--quiet``, ``--progress`` and ``--no-cache`` (every sub-command has them)."""
    group = parser.add_argument_group("run options")
    group.add_argument("--quiet", action="store_true", help="no progress display")
    group.add_argument("--progress", action="store_true",
                       help="show the progress display at once, even when standard error is not a terminal")
    group.add_argument("--no-cache", action="store_true",
                       help=f"do not read or write the form-finding cache (same as {NO_CACHE_ENV}=1)")


def progress_enabled(args: argparse.Namespace) -> bool:
    """Whether to show progress: ``--progress``, else not with ``--quiet``, else on a terminal only.

    Raises
    ------
    ModelError
        If both ``--quiet`` and ``--progress`` are given.
    """
    quiet, forced = getattr(args, "quiet", False), getattr(args, "progress", False)
    if quiet and forced:
        raise ModelError("give at most one of --quiet and --progress")
    return forced or (not quiet and sys.stderr.isatty())


class Progress:
    """The progress display of long work: a tqdm bar on standard error.

    Call it with a short message before each step (the one protocol of the API's ``progress``
    callbacks: ``Callable[[str], None]``); it shows the message, the steps done of ``total`` if
    known (else the message alone, which carries its own count) and the elapsed time. It is the only
    place that draws progress: the library only calls back.
    Shown only after :data:`PROGRESS_DELAY` and only when :func:`progress_enabled`: once the delay has
    passed, a background thread draws the last message and redraws the elapsed time every
    :data:`PROGRESS_TICK`, so that a long first step (the first four units of a sweep) shows at once
    too. Use it as a context manager so that the bar and its thread are closed. Standard output is
    untouched (JSON stays pure).

    Parameters
    ----------
    enabled : bool
        Whether to show anything.
    total : int, optional
        Number of steps, if known. [-]
    delay : float
        Seconds before the display appears. [s]
    """

    def __init__(self, enabled: bool, total: int | None = None, delay: float = PROGRESS_DELAY):
        from tqdm import tqdm

        self._bar = tqdm(total=total, file=sys.stderr, disable=not enabled, delay=delay, leave=False,
                         dynamic_ncols=True, unit="step",
                         bar_format="{desc}: {n_fmt}/{total_fmt} steps [{elapsed}]" if total else "{desc} [{elapsed}]")
        self._shown_after = time.monotonic() + delay
        self._started = False
        self._lock = threading.Lock()
        self._closed = threading.Event()
        self._ticker = None
        if enabled:
            self._ticker = threading.Thread(target=self._tick, args=(delay,), name="presag-progress", daemon=True)
            self._ticker.start()

    def __call__(self, message: str) -> None:
        with self._lock:
            if self._started:
                self._bar.update(1)
            self._started = True
            # tqdm's own refresh would ignore the delay; short work shows nothing
            self._bar.set_description_str(message, refresh=time.monotonic() >= self._shown_after)

    def _tick(self, delay: float) -> None:
        """Draw the display when the delay has passed, then redraw it every :data:`PROGRESS_TICK`."""
        if self._closed.wait(delay):
            return
        while True:
            with self._lock:
                if self._closed.is_set():
                    return
                if self._started:
                    self._bar.refresh()
            if self._closed.wait(PROGRESS_TICK):
                return

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc: object) -> None:
        with self._lock:
            self._closed.set()
        if self._ticker is not None:
            self._ticker.join()
        self._bar.close()


def progress(args: argparse.Namespace, total: int | None = None) -> Progress:
    """The :class:`Progress` display for a sub-command's options: off with ``--quiet``; with
    ``--progress`` at once, else on a terminal after :data:`PROGRESS_DELAY`.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed options of the sub-command.
    total : int, optional
        Number of steps to be counted (None: unknown). [-]
    """
    return Progress(progress_enabled(args), total, delay=0.0 if getattr(args, "progress", False) else PROGRESS_DELAY)


def add_json_flag(parser: argparse.ArgumentParser) -> None:
    """Add ``--json``."""
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of tables")


def print_json(obj: Any) -> None:
    """Print an object as JSON (numpy arrays and scalars converted; NaN/inf become null).

    A dict gets the key ``warnings``: its own warnings followed by every other warning the command
    has shown (:func:`shown_warnings`), each once.
    """
    if isinstance(obj, dict):
        own = [" ".join(str(w).split()) for w in obj.get("warnings", [])]
        obj = {**obj, "warnings": list(dict.fromkeys([*own, *shown_warnings()]))}
    print(json.dumps(_plain(obj), indent=2, allow_nan=False))


def _plain(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {str(k): _plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_plain(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _plain(obj.tolist())
    if isinstance(obj, (np.floating, float)):
        value = float(obj)
        return value if math.isfinite(value) else None
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    return obj


def table(headers: Sequence[str], rows: Sequence[Sequence[Any]], formats: Sequence[str] | None = None) -> str:
    """A plain-text table with right-aligned columns."""
    formats = formats or ["{}"] * len(headers)
    cells = [[fmt.format(v) if v is not None else "-" for fmt, v in zip(formats, row)] for row in rows]
    widths = [max(len(h), *(len(r[i]) for r in cells)) if cells else len(h) for i, h in enumerate(headers)]
    lines = ["  ".join(h.rjust(w) for h, w in zip(headers, widths)), "  ".join("-" * w for w in widths)]
    lines += ["  ".join(c.rjust(w) for c, w in zip(row, widths)) for row in cells]
    return "\n".join(lines)


def positive_float(text: str) -> float:
    """argparse type: a finite number (range checks are the API's)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"{text!r} is not a finite number")
    return value


def float_list(text: str) -> list[float]:
    """argparse type: a list of values ``A,B,C`` (one value is a list of one).

    A band ``LOW:HIGH`` where a list is expected is refused with a hint.
    """
    if ":" in text:
        raise argparse.ArgumentTypeError(
            f"{text!r}: this option takes a list of values A,B,C (e.g. 50,100,150); LOW:HIGH is the band syntax"
        )
    values = [positive_float(part) for part in text.split(",") if part.strip()]
    if not values:
        raise argparse.ArgumentTypeError(f"{text!r}: give at least one value, e.g. 50 or 50,100,150")
    return values


def band(text: str) -> tuple[float, float]:
    """argparse type: a band ``LOW:HIGH`` (one value: LOW = HIGH); ranges are the API's to check.

    A list ``A,B`` where a band is expected is refused with a hint.
    """
    if "," in text:
        raise argparse.ArgumentTypeError(
            f"{text!r}: a band is written LOW:HIGH (e.g. {text.replace(',', ':')}); A,B,C is the list syntax"
        )
    parts = text.split(":")
    if len(parts) > 2:
        raise argparse.ArgumentTypeError(f"{text!r}: a band is written LOW:HIGH, e.g. 70:148")
    low, high = (positive_float(p) for p in (parts * 2)[:2])
    return low, high


def output_folder(text: str, option: str = "--out") -> Path:
    """Check an output folder before the work starts: an existing folder, or a new one in an existing
    folder; it must accept a new file (tried, not guessed). Return its path (created if missing).

    Raises
    ------
    ModelError
        If the path is a file, its parent folder is missing, or the folder is not writable.
    """
    path = Path(text)
    if path.exists() and not path.is_dir():
        raise ModelError(f"{option} {text}: is a file; give a folder")
    if not path.exists() and not path.parent.is_dir():
        raise ModelError(f"{option} {text}: the folder {path.parent} does not exist")
    try:
        path.mkdir(exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=path, prefix=".presag-probe-"):
            pass
    except OSError as exc:
        raise ModelError(f"{option} {text}: cannot write into it ({exc.strerror or exc})") from None
    return path


def announcer(args: argparse.Namespace) -> Callable[[str], None] | None:
    """The ``announce`` of a job for a command: print each notice on stderr as ``presag: …``; None
    with ``--quiet``."""
    if getattr(args, "quiet", False):
        return None
    return lambda text: print(f"presag: {text}", file=sys.stderr, flush=True)


def announce_work(args: argparse.Namespace, estimate: Any) -> None:
    """Say what long work will cost (time and memory) before it starts, unless ``--quiet``
    (:func:`~presag_opt.dynamics.cost.work_notice`).

    Parameters
    ----------
    args : argparse.Namespace
        The command's options (``--quiet``).
    estimate : object
        With ``seconds`` [s] and ``describe()``, e.g. a :class:`~presag_opt.dynamics.cost.WorkEstimate`.
    """
    from presag_opt.dynamics.cost import work_notice

    say, text = announcer(args), work_notice(estimate)
    if say and text:
        say(text)


def form_find_for(args: argparse.Namespace, catenary: Catenary, settings: StaticSettings) -> EquilibriumState:
    """Form-find for a command: say beforehand when it will take long (unless ``--quiet``).

    Parameters
    ----------
    args : argparse.Namespace
        The command's options (``--quiet``).
    catenary : Catenary
        System model.
    settings : StaticSettings
        Numerical settings.
    """
    from presag_opt.static.form_finding import form_find
    from presag_opt.static.run_time import form_find_estimate

    announce_form_finding(args, *form_find_estimate(catenary, settings))
    return form_find(catenary, settings)


def announce_form_finding(args: argparse.Namespace, n_nodes: int, seconds: float) -> None:
    """Say beforehand that a form-finding of ``n_nodes`` nodes will take ``seconds``, if that is long
    (:func:`~presag_opt.dynamics.cost.form_finding_notice`; not with ``--quiet``).

    Parameters
    ----------
    args : argparse.Namespace
        Parsed command line (its ``quiet`` flag, when present, silences the message).
    n_nodes : int
        Nodes of the model to be form-found. [-]
    seconds : float
        Estimated run time of the form-finding. [s]
    """
    from presag_opt.dynamics.cost import form_finding_notice

    say, text = announcer(args), form_finding_notice(n_nodes, seconds)
    if say and text:
        say(text)


def model_help(kind: str, default: str | None = None) -> str:
    """Help line of a model argument: file or built-in name, listing the built-in ones.

    Parameters
    ----------
    kind : str
        ``catenaries``, ``pantographs``, ``cases`` or ``studies``.
    default : str, optional
        The default model, if any.
    """
    from presag_opt.system.loader import builtin_model_names

    text = f"model file or built-in name ({', '.join(builtin_model_names(kind))})"
    return text + (f"; default {default}" if default else "")


def print_warnings(messages: Iterable[str]) -> None:
    """Print each warning as one line ``presag: warning: …`` on standard error, once per command
    (a message already shown, raised or printed, is not repeated); :func:`print_json` lists them."""
    shown = _SHOWN_WARNINGS.get({})
    for message in messages:
        text = " ".join(str(message).split())
        if text and text not in shown:
            shown[text] = None
            print(f"presag: warning: {text}", file=sys.stderr, flush=True)


def report_failures(command: str, summary: str) -> int:
    """The end of a long analysis: one line on standard error when some of its evaluations failed.

    Parameters
    ----------
    command : str
        The sub-command, e.g. ``sensitivity``.
    summary : str
        The analysis' one-line summary of its failures ("" when none failed).

    Returns
    -------
    int
        The exit status: 0, or :data:`EXIT_PARTIAL` after failures. [-]
    """
    if not summary:
        return 0
    print(f"presag {command}: {summary}", file=sys.stderr, flush=True)
    return EXIT_PARTIAL


def shown_warnings() -> list[str]:
    """The warnings the running command has shown so far, in order."""
    return list(_SHOWN_WARNINGS.get({}))


def add_plot_option(parser: argparse.ArgumentParser, figures: str) -> None:
    """``--plot DIR``, the one kind of plot option: the command's figures as PNG files in a folder.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The sub-command's parser.
    figures : str
        What the command draws, for the help text.
    """
    parser.add_argument("--plot", metavar="DIR", default=None,
                        help=f"save {figures} as PNG files into this folder (created if missing)")


def plot_folder(args: argparse.Namespace) -> Path | None:
    """The checked ``--plot`` folder (before any work), or None without ``--plot``."""
    return output_folder(args.plot, "--plot") if getattr(args, "plot", None) else None
