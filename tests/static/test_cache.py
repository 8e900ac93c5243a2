"""The form-finding cache: the same state back from a cached file, a changed model recomputed, a
corrupt file ignored and rewritten, the most recently used entries kept."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

REPOSITORY = Path(__file__).resolve().parents[2]


@pytest.fixture
def cache_folder(tmp_path, test_runtime):
    """A runtime whose form-finding cache is an empty folder of this test's."""
    folder = tmp_path / "cache"
    with test_runtime.replace(state_cache=folder):
        yield folder


def _small_model(tmp_path: Path, height: float = 5.3) -> Path:
    """A three-span copy of the ST 9,8/9,8 ideal model (form-finds in about a second)."""
    text = (REPOSITORY / "models" / "catenaries" / "st_9.8_ideal.toml").read_text()
    out = []
    for line in text.splitlines():
        if line.startswith("span_count"):
            line = 'span_count = { value = 3, unit = "-", source = "assumed" }'
        if line.startswith("contact_wire_height"):
            line = f'contact_wire_height = {{ value = {height}, unit = "m", source = "assumed" }}'
        out.append(line)
    path = tmp_path / "small.toml"
    path.write_text("\n".join(out) + "\n")
    return path


def test_cache_returns_the_same_state_and_a_changed_model_is_recomputed(tmp_path, cache_folder, monkeypatch):
    from presag_opt.static import form_finding
    from presag_opt.system.loader import load_catenary

    model = _small_model(tmp_path)
    assert "span_count = { value = 3" in model.read_text()
    first = form_finding.form_find(load_catenary(model))
    assert len(list(cache_folder.glob("state-*.npz"))) == 1

    def no_solve(*args):
        raise AssertionError("form-finding ran although the state is cached")

    with monkeypatch.context() as patch:
        patch.setattr(form_finding, "_form_find", no_solve)
        again = form_finding.form_find(load_catenary(model))
    np.testing.assert_array_equal(again.positions, first.positions)
    np.testing.assert_array_equal(again.params.unstretched_length, first.params.unstretched_length)
    # the statistics of the solve that made it come back with it, marked as read from the cache
    assert not first.form_finding.cached and again.form_finding == dataclasses.replace(first.form_finding, cached=True)

    changed = form_finding.form_find(load_catenary(_small_model(tmp_path, height=5.5)))  # the file edited
    assert len(list(cache_folder.glob("state-*.npz"))) == 2
    assert changed.positions[:, 2].max() > first.positions[:, 2].max()


def test_a_corrupt_cache_file_is_ignored_and_rewritten(tmp_path, cache_folder):
    from presag_opt.static.form_finding import form_find
    from presag_opt.system.loader import load_catenary

    catenary = load_catenary(_small_model(tmp_path))
    reference = form_find(catenary)
    (entry,) = cache_folder.glob("state-*.npz")
    entry.write_bytes(b"not a zip file")
    state = form_find(catenary)
    np.testing.assert_array_equal(state.positions, reference.positions)
    with np.load(entry) as data:  # rewritten as a readable file
        np.testing.assert_array_equal(data["positions"], reference.positions)


def test_cache_keeps_the_most_recently_used_entries(cache_folder):
    from presag_opt.static import cache

    for i in range(cache.MAX_ENTRIES + 3):
        cache.store(f"key{i}", {"positions": np.full(3, float(i))})
    assert len(list(cache_folder.glob("state-*.npz"))) == cache.MAX_ENTRIES
    assert cache.load("key0") is None and cache.load(f"key{cache.MAX_ENTRIES + 2}") is not None


def test_long_analyses_keep_their_evaluations_in_the_cache_folder_most_recent_first(cache_folder):
    import os

    from presag_opt import runtime
    from presag_opt.static import cache

    folders = []
    for i in range(cache.MAX_EVALUATION_STORES + 2):
        folder = cache.evaluation_folder("sensitivity-robust", f"{i:04d}")
        folder.mkdir(parents=True)
        os.utime(folder, (1e9 + i, 1e9 + i))  # opened in this order
        folders.append(folder)
    assert folders[0] == cache_folder / "evaluations" / "sensitivity-robust-0000"
    # opening one more keeps it and the most recently used others, MAX_EVALUATION_STORES in all
    newest = cache.evaluation_folder("monte-carlo", "abcd")
    kept = sorted(p.name for p in (cache_folder / "evaluations").iterdir())
    assert kept == sorted(f.name for f in folders[-(cache.MAX_EVALUATION_STORES - 1):])
    assert not newest.exists()  # created by the store that opens it
    assert cache.clear_evaluations(cache_folder) == cache.MAX_EVALUATION_STORES - 1
    assert not list((cache_folder / "evaluations").iterdir())
    with runtime.current().replace(state_cache=None):
        assert cache.evaluation_folder("monte-carlo", "abcd") is None  # no cache: nothing is kept
