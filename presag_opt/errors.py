"""Exceptions raised by presag_opt.

Every error a user can cause carries a message that names the offending field, its value, its unit
and the valid range, so that the command line can print it as one line.
"""

from __future__ import annotations

from typing import Any


class PresagError(Exception):
    """Base class of all presag_opt errors."""


class ModelError(PresagError, ValueError):
    """A system model, a setting or an argument is malformed or out of its valid range."""


class ConvergenceError(PresagError, RuntimeError):
    """A numerical solver did not converge; no partial result is returned.

    Attributes
    ----------
    stats : dict
        The solver's own statistics (for IPOPT: ``return_status``, iteration count, ...).
    """

    def __init__(self, message: str, stats: dict[str, Any] | None = None):
        super().__init__(message)
        self.stats = dict(stats or {})


class StorageError(PresagError, OSError):
    """A file could not be written or read (no space left, no permission, a read-only folder, a file
    where a folder should be). The message is one line naming the path, the cause and what to do;
    ``errno`` and ``filename`` are those of the failed operation."""

    def __init__(self, message: str, errno: int | None = None, filename: str | None = None):
        super().__init__(errno, message, filename)
        self.message = message

    def __str__(self) -> str:
        return self.message


def failure_reason(exc: BaseException) -> str:
    """One line saying why a computation failed: the message of an expected error (this module's), else
    the error's type and message (``MemoryError: out of memory`` for one without a message).

    Parameters
    ----------
    exc : BaseException
        The error.
    """
    first = str(exc).splitlines()[0] if str(exc) else ""
    if isinstance(exc, PresagError):
        return first
    if isinstance(exc, MemoryError):
        return f"MemoryError: {first or 'out of memory'}"
    return f"{type(exc).__name__}: {first}" if first else type(exc).__name__
