"""Files written so that they are either absent, old or complete, and the one line a failed write gives.

:func:`write_atomic` writes to a temporary file in the same folder (its name ends in
:data:`TEMPORARY_SUFFIX`), flushes and fsyncs it, renames it over its final name with
:func:`os.replace` and fsyncs the folder: a process killed at any moment leaves the old file or the
new one, never a part. :func:`storage_errors` turns a failed file operation into one
:class:`~presag_opt.errors.StorageError` line naming the path, the cause and what to do. The
resumable stores (study units, sensitivity samples, Monte Carlo realisations) write through them.
"""

from __future__ import annotations

import errno
import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from presag_opt.errors import StorageError

TEMPORARY_SUFFIX = ".partial"
"""Name ending of a file being written (removed when the write fails; a stray one is a killed write)."""


@contextmanager
def storage_errors(path: Path) -> Iterator[None]:
    """Turn a failed file operation under ``path`` into one :class:`~presag_opt.errors.StorageError`
    line naming the file, the cause and what to do (the study resumes once it is fixed)."""
    try:
        yield
    except StorageError:
        raise
    except OSError as exc:
        name = exc.filename or path
        reason = exc.strerror or str(exc)
        if isinstance(exc, (FileExistsError, NotADirectoryError)):
            reason, hint = "a file is where a folder should be", "move it or give another output path"
        else:
            hint = {
                errno.ENOSPC: "free some space",
                errno.EDQUOT: "free some space (disk quota)",
                errno.EACCES: "give write permission or another output path",
                errno.EPERM: "give write permission or another output path",
                errno.EROFS: "give a writable output path",
            }.get(exc.errno or 0, "fix the cause")
        raise StorageError(
            f"{name}: {reason}; {hint}, then run the same command again: finished units are kept",
            exc.errno, str(name),
        ) from None


def write_atomic(path: Path, content: bytes) -> None:
    """Write ``content`` to ``path`` so that the file is either absent, old, or complete.

    Parameters
    ----------
    path : pathlib.Path
        Final file name.
    content : bytes
        The file content.

    Raises
    ------
    StorageError
        The file cannot be written (the temporary is removed).
    """
    with storage_errors(path):
        handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=path.name + ".", suffix=TEMPORARY_SUFFIX)
        try:
            with os.fdopen(handle, "wb") as fh:
                fh.write(content)
                fh.flush()
                os.fsync(fh.fileno())
            os.replace(temporary, path)
        except BaseException:
            Path(temporary).unlink(missing_ok=True)
            raise
        _fsync_directory(path.parent)


def _fsync_directory(folder: Path) -> None:
    """Make a rename in ``folder`` durable."""
    fd = os.open(folder, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)
