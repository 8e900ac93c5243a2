"""Solver statistics as data: a recording collects every form-finding inside it (nested ones too, and only
in its own context), and the summary counts the solves and gives their quantiles without the cached ones."""

from __future__ import annotations

import threading

import pytest

from presag_opt.static.solver_statistics import FormFindingStatistics, record, recording, statistics_summary


def solve(iterations: int, seconds: float, *, passes: int = 1, restarts: int = 0, cached: bool = False):
    return FormFindingStatistics(passes=passes, ipopt_iterations=iterations - 1, newton_iterations=1,
                                 restarts=restarts, seconds=seconds, cached=cached)


def test_a_recording_collects_what_runs_inside_it_and_nothing_outside():
    record(solve(3, 1.0))  # outside any recording: kept nowhere
    with recording() as outer:
        record(solve(4, 1.0))
        with recording() as inner:
            record(solve(5, 2.0))
        record(solve(6, 3.0))
    assert [s.iterations for s in outer] == [4, 6] and [s.iterations for s in inner] == [5]
    seen = []

    def elsewhere():
        with recording() as mine:
            record(solve(7, 1.0))
        seen.append(mine)

    with recording() as here:
        thread = threading.Thread(target=elsewhere)
        thread.start()
        thread.join()
    assert here == [] and [s.iterations for s in seen[0]] == [7]  # each thread its own recording


def test_the_summary_counts_solves_and_quantiles_them_without_the_cached_ones():
    found = [solve(n, 0.1 * n) for n in range(1, 11)] + [solve(2, 5.0, passes=2, restarts=1),
                                                         solve(99, 99.0, cached=True)]
    summary = statistics_summary(found)
    assert (summary["form_findings"], summary["cached"], summary["restarts"], summary["passes_above_one"]) == (11, 1, 1, 1)
    iterations = sorted([*range(1, 11), 2])  # 11 solves: the median is the 6th
    assert summary["iterations"]["q50"] == iterations[5] and summary["iterations"]["q100"] == 10.0
    assert summary["seconds"]["q100"] == pytest.approx(5.0, abs=1e-12)
    assert statistics_summary([])["iterations"] == {}


def test_the_statistics_go_to_json_and_back():
    stats = solve(4, 1.5, passes=2, restarts=1)
    assert FormFindingStatistics.from_dict(stats.to_dict()) == stats
    assert stats.to_dict()["ipopt_iterations"] == 3 and stats.iterations == 4
