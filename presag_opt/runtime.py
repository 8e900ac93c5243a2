"""The run-time settings of a computation: one frozen :class:`Runtime`, entered as a context.

What a computation does never depends on where it runs, but how it runs does: whether form-found
states are read from and written to a cache folder, whether C libraries are compiled on this
machine (and where they are kept), and whether an unexpected error shows its traceback. Those
choices are one :class:`Runtime` object instead of switches scattered over the package:

- the ``presag`` command line builds it from its options and the environment
  (:meth:`Runtime.from_environment`) and runs the command inside it (``with runtime: ...``);
- library code reads the one in force with :func:`current` when it needs it, at the moment it needs
  it (never at import, never cached for the life of the process);
- :func:`presag_opt.processes.worker_pool` hands the runtime in force to every worker process it
  starts (pickled under spawn, inherited under fork), so a worker caches and compiles exactly as its
  parent does, whatever the start method;
- outside any ``with`` block, :func:`current` is :meth:`Runtime.from_environment` without the state
  cache: a script that imports the package form-finds afresh unless it asks for the cache.

Entering a runtime is scoped to the ``with`` block (a ``contextvars.ContextVar``, so two threads
or two tests do not see each other's); nothing of it outlives the block.

Examples
--------
>>> from presag_opt.runtime import Runtime
>>> with Runtime.from_environment(state_cache=True):
...     state = form_find(load_catenary("st_9.8_ideal"))   # doctest: +SKIP
"""

from __future__ import annotations

import contextvars
import dataclasses
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

NO_CACHE_ENV = "PRESAG_NO_CACHE"
"""Environment variable that, set to anything but "" or "0", turns the form-finding cache off."""

NO_COMPILE_ENV = "PRESAG_NO_COMPILE"
"""Environment variable that, set to anything but "" or "0", turns all compiled C code off."""

DEBUG_ENV = "PRESAG_DEBUG"
"""Environment variable that, set to anything but "", shows the traceback of an unexpected error."""


def _set(environ: Mapping[str, str], name: str) -> bool:
    return environ.get(name, "") not in ("", "0")


def default_cache_directory(environ: Mapping[str, str] | None = None) -> Path:
    """``$XDG_CACHE_HOME/presag_opt``, or ``~/.cache/presag_opt``: the package's folder in the user's
    cache (form-found states in it, compiled libraries in its ``compiled`` subfolder).

    Parameters
    ----------
    environ : mapping, optional
        Environment to read (default: the process's).
    """
    environ = os.environ if environ is None else environ
    base = environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "presag_opt"


@dataclass(frozen=True, kw_only=True)
class Runtime:
    """How a computation runs: its caches, compiled code and error display (never its numbers).

    Attributes
    ----------
    state_cache : Path or None
        Folder of the form-finding cache (:mod:`presag_opt.static.cache`); None: every state is
        form-found afresh and nothing is written.
    compile : bool
        Build and use the C libraries of :mod:`presag_opt.native` (the static model's element
        functions, the banded solve, the batch simulator's sweeps); False: their fallbacks (CasADi's
        virtual machine, numba, LAPACK), which give the same numbers.
    library_folder : Path
        Folder of the compiled C libraries.
    debug : bool
        The command line prints the traceback of an unexpected error (not only its one line).
    """

    state_cache: Path | None = None
    compile: bool = True
    library_folder: Path = dataclasses.field(default_factory=lambda: default_cache_directory() / "compiled")
    debug: bool = False

    @classmethod
    def from_environment(cls, environ: Mapping[str, str] | None = None, *, state_cache: bool = False) -> Runtime:
        """The runtime the environment asks for.

        Reads ``XDG_CACHE_HOME`` (the cache folders), ``PRESAG_NO_COMPILE``, ``PRESAG_DEBUG`` and, when
        ``state_cache`` is asked for, ``PRESAG_NO_CACHE`` (which then turns it off again).

        Parameters
        ----------
        environ : mapping, optional
            Environment to read (default: the process's, read now).
        state_cache : bool
            Use the form-finding cache in :func:`default_cache_directory` (the command line's
            default; the library's default is no cache).
        """
        environ = os.environ if environ is None else environ
        folder = default_cache_directory(environ)
        return cls(state_cache=folder if state_cache and not _set(environ, NO_CACHE_ENV) else None,
                   compile=not _set(environ, NO_COMPILE_ENV), library_folder=folder / "compiled",
                   debug=bool(environ.get(DEBUG_ENV, "")))

    def replace(self, **changes: object) -> Runtime:
        """A copy with some fields changed (e.g. ``runtime.replace(state_cache=None)``)."""
        return dataclasses.replace(self, **changes)

    def activate(self) -> None:
        """Put this runtime in force for the rest of the current context, with no ``with`` block: for
        a notebook's first cell, a script's start or a worker process (a ``with`` block entered
        later still takes precedence inside it)."""
        _CURRENT.set(self)

    def __enter__(self) -> Runtime:
        _TOKENS.set((*_TOKENS.get(), _CURRENT.set(self)))
        return self

    def __exit__(self, *exc: object) -> None:
        *outer, token = _TOKENS.get()
        _TOKENS.set(tuple(outer))
        _CURRENT.reset(token)


_CURRENT: contextvars.ContextVar[Runtime] = contextvars.ContextVar("presag_runtime")
"""The runtime entered last in this context (unset outside every ``with`` block)."""

_TOKENS: contextvars.ContextVar[tuple[contextvars.Token, ...]] = contextvars.ContextVar("presag_runtime_tokens",
                                                                                       default=())
"""The reset tokens of the runtimes entered in this context, innermost last (a frozen object cannot keep them)."""


def current() -> Runtime:
    """The runtime in force: the innermost one entered, else :meth:`Runtime.from_environment` (no
    form-finding cache)."""
    try:
        return _CURRENT.get()
    except LookupError:
        return Runtime.from_environment()
