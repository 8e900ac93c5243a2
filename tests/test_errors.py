"""``presag_opt.errors``: the exception classes carry what the command line and callers rely on — a
ModelError is a ValueError, a ConvergenceError keeps its own copy of the solver's statistics, a
StorageError is an OSError whose text is the one line (not ``[Errno 28] …``)."""

from __future__ import annotations

import errno

import pytest

from presag_opt.errors import ConvergenceError, ModelError, PresagError, StorageError


def test_every_error_is_a_presag_error_and_the_builtin_kind_callers_catch():
    assert issubclass(ModelError, ValueError) and issubclass(ConvergenceError, RuntimeError)
    assert issubclass(StorageError, OSError)
    assert all(issubclass(e, PresagError) for e in (ModelError, ConvergenceError, StorageError))


def test_a_convergence_error_keeps_a_copy_of_the_solver_statistics():
    stats = {"return_status": "Maximum_Iterations_Exceeded", "iter_count": 3000}
    exc = ConvergenceError("IPOPT did not converge", stats)
    stats["iter_count"] = 0
    assert exc.stats == {"return_status": "Maximum_Iterations_Exceeded", "iter_count": 3000}
    assert str(exc) == "IPOPT did not converge" and ConvergenceError("x").stats == {}


def test_a_storage_error_reads_as_its_one_line_and_keeps_errno_and_file():
    exc = StorageError("/data/s.nc: no space left; free some space", errno.ENOSPC, "/data/s.nc")
    assert str(exc) == exc.message == "/data/s.nc: no space left; free some space"
    assert (exc.errno, exc.filename) == (errno.ENOSPC, "/data/s.nc")
    with pytest.raises(OSError, match="no space left"):
        raise exc
