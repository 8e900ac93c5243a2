"""atomic_files.py: a file is absent, old or complete, and a failed write is one line naming the path."""

from __future__ import annotations

import os

import pytest

from presag_opt.atomic_files import TEMPORARY_SUFFIX, write_atomic
from presag_opt.errors import StorageError


def test_a_write_replaces_the_old_file_whole_and_leaves_no_temporary(tmp_path):
    path = tmp_path / "unit.json"
    write_atomic(path, b"old")
    write_atomic(path, b"new content")
    assert path.read_bytes() == b"new content"
    assert [p.name for p in tmp_path.iterdir()] == ["unit.json"]


def test_a_write_killed_before_the_rename_keeps_the_old_file(tmp_path, monkeypatch):
    path = tmp_path / "unit.json"
    write_atomic(path, b"old")

    def killed(*args):
        raise KeyboardInterrupt

    monkeypatch.setattr(os, "replace", killed)
    with pytest.raises(KeyboardInterrupt):
        write_atomic(path, b"new")
    assert path.read_bytes() == b"old"
    assert not list(tmp_path.glob(f"*{TEMPORARY_SUFFIX}"))  # the temporary is removed


def test_a_failed_write_is_one_line_naming_the_path_and_what_to_do(tmp_path):
    path = tmp_path / "missing" / "unit.json"
    with pytest.raises(StorageError) as caught:
        write_atomic(path, b"x")
    message = str(caught.value)
    assert "\n" not in message and str(tmp_path / "missing") in message
    assert "run the same command again" in message
