"""Storage faults of a study store: one line each, nothing half-written, the study resumes.

A full disk and a read-only folder are real: a 2 MB tmpfs is mounted for the module (root only; the
tests that need it, tier e2e, are skipped where mounting is not possible). A permission lost in the middle of
a study, and a full disk where tmpfs is not available, are injected as the ``OSError`` the write
raises. Every resumed store is compared byte for byte with an undisturbed run of the same study.
"""

from __future__ import annotations

import errno
import os
import subprocess
import tempfile
from pathlib import Path

import pytest

from presag_opt.errors import StorageError
from presag_opt.studies import store as store_module
from presag_opt.studies.definition import load_study
from presag_opt.studies.runner import run_study
from presag_opt.studies.store import units_directory

STUDY = Path(__file__).parent / "models" / "small_grid.toml"
TMPFS_SIZE = 2 * 1024 * 1024
"""Size of the test file system. [B]"""


@pytest.fixture(scope="module")
def reference(tmp_path_factory) -> bytes:
    """The bytes of the small study's store, undisturbed."""
    path = tmp_path_factory.mktemp("reference") / "study.nc"
    run_study(load_study(STUDY), path, workers=1)
    return path.read_bytes()


@pytest.fixture(scope="module")
def tmpfs():
    """A freshly mounted 2 MB tmpfs (skipped where it cannot be mounted), unmounted afterwards."""
    folder = Path(tempfile.mkdtemp(prefix="presag-tmpfs-"))
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={TMPFS_SIZE}", "tmpfs", str(folder)],
                             capture_output=True, check=False)
    if mounted.returncode != 0:
        folder.rmdir()
        pytest.skip("cannot mount a tmpfs here (needs root): the injected faults below still run")
    yield folder
    subprocess.run(["umount", str(folder)], check=False)
    folder.rmdir()


@pytest.fixture
def empty_tmpfs(tmpfs):
    for entry in tmpfs.iterdir():
        subprocess.run(["rm", "-rf", str(entry)], check=True)
    yield tmpfs
    subprocess.run(["mount", "-o", "remount,rw", str(tmpfs)], check=False)


def _fill(folder: Path, leave: int) -> Path:
    """Fill the file system of ``folder`` up to ``leave`` bytes free; return the filler file."""
    filler = folder / "filler"
    with open(filler, "wb") as fh:
        try:
            while os.statvfs(folder).f_bavail * os.statvfs(folder).f_frsize > leave:
                fh.write(b"\0" * 4096)
                fh.flush()
        except OSError:
            pass
    return filler


def _sweep(presag, out: Path):
    return presag("sweep", str(STUDY), "--out", str(out), "--workers", "2", "--quiet")


def _partials(folder: Path) -> list[Path]:
    return [p for p in folder.rglob("*") if p.name.endswith(store_module.TEMPORARY_SUFFIX)]


def _one_error_line(run) -> str:
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1, run.stderr
    assert lines[0].startswith("presag: error: ")
    return lines[0]


@pytest.mark.e2e  # mounts a real file system
def test_a_full_disk_before_the_manifest_is_one_line_and_resumes(presag, empty_tmpfs, reference):
    out = empty_tmpfs / "study.nc"
    filler = _fill(empty_tmpfs, leave=0)
    run = _sweep(presag, out)
    assert run.returncode == 4
    line = _one_error_line(run)
    assert "No space left on device; free some space, then run the same command again" in line
    assert not _partials(empty_tmpfs) and not out.exists()
    assert not (units_directory(out) / store_module.LOCK).exists()
    filler.unlink()
    run = _sweep(presag, out)
    assert run.returncode == 0, run.stderr
    assert out.read_bytes() == reference


@pytest.mark.e2e  # mounts a real file system
def test_a_full_disk_at_the_store_keeps_the_units_and_resumes_without_recomputing(presag, empty_tmpfs, reference):
    out = empty_tmpfs / "study.nc"
    # Room for the manifest, the lock and the four unit files (one 4 kB page each), not for the
    # store (about 30 kB).
    filler = _fill(empty_tmpfs, leave=7 * 4096)
    run = _sweep(presag, out)
    assert run.returncode == 4
    assert f"{out}: No space left on device" in _one_error_line(run)
    assert not _partials(empty_tmpfs) and not out.exists()
    assert len(list(units_directory(out).glob("s*_v*.json"))) == 4
    filler.unlink()
    resumed = run_study(load_study(STUDY), out, workers=1)
    assert resumed.units_computed == 0
    assert out.read_bytes() == reference


@pytest.mark.e2e  # mounts a real file system
def test_a_read_only_folder_is_one_line(presag, empty_tmpfs):
    subprocess.run(["mount", "-o", "remount,ro", str(empty_tmpfs)], check=True)
    run = _sweep(presag, empty_tmpfs / "study.nc")
    assert run.returncode == 4
    assert "Read-only file system; give a writable output path" in _one_error_line(run)
    assert not list(empty_tmpfs.iterdir())


def test_a_file_where_the_units_folder_should_be_is_one_line(presag, tmp_path):
    out = tmp_path / "study.nc"
    units_directory(out).write_text("not a folder")
    run = _sweep(presag, out)
    assert run.returncode == 4
    assert "a file is where a folder should be; move it or give another output path" in _one_error_line(run)
    assert units_directory(out).read_text() == "not a folder"


def test_a_file_where_the_stores_folder_should_be_is_one_line(presag, tmp_path):
    (tmp_path / "plain").write_text("x")
    run = _sweep(presag, tmp_path / "plain" / "study.nc")
    assert run.returncode == 2
    assert "plain is a file, not a folder" in _one_error_line(run)


@pytest.mark.parametrize("code", [errno.EACCES, pytest.param(errno.ENOSPC, marks=pytest.mark.slow)])
def test_a_write_failing_in_the_middle_leaves_complete_files_and_resumes(tmp_path, monkeypatch, reference, code):
    """The third atomic write (manifest, unit, *unit*) fails as a lost permission or a full disk does."""
    out = tmp_path / "study.nc"
    real = store_module.os.replace
    calls = []

    def failing_replace(source, target):  # os.replace of the whole process: count the store's own only
        if str(target).startswith(str(tmp_path)):
            calls.append(target)
        if len(calls) == 3 and calls[-1] == target:
            raise OSError(code, os.strerror(code), str(target))
        return real(source, target)

    monkeypatch.setattr(store_module.os, "replace", failing_replace)
    with pytest.raises(StorageError, match="then run the same command again: finished units are kept") as caught:
        run_study(load_study(STUDY), out, workers=1)
    assert caught.value.errno == code
    assert not _partials(tmp_path) and not out.exists()
    assert len(list(units_directory(out).glob("s*_v*.json"))) == 1
    assert not (units_directory(out) / store_module.LOCK).exists()
    monkeypatch.setattr(store_module.os, "replace", real)
    resumed = run_study(load_study(STUDY), out, workers=1)
    assert resumed.units_computed == 3
    assert out.read_bytes() == reference
