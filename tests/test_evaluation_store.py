"""evaluation_store.py: finished and failed evaluations kept one file each under the analysis' key; a
folder of another analysis refused; the key changes with any input."""

from __future__ import annotations

import json
import math

import pytest

from presag_opt.errors import ModelError
from presag_opt.evaluation_store import MANIFEST, Evaluation, EvaluationStore, analysis_key


def test_evaluations_come_back_as_written_failures_too(tmp_path):
    store = EvaluationStore.open(tmp_path / "s", analysis_key("screening", 3), "a screening")
    done = Evaluation(index=0, inputs={"catenary.system_height": 1.2}, values={"presag_rel": 1.1},
                      solver={"form_findings": [{"passes": 1}]}, seconds=0.5)
    failed = Evaluation(index=4, inputs={"catenary.system_height": 0.3}, failure="span 1 (30 m): no room", seconds=0.1)
    reference = Evaluation(index=-1, values={"worst": 0.2}, seconds=2.0)
    for evaluation in (done, failed, reference):
        store.write(evaluation)
    assert sorted(p.name for p in (tmp_path / "s").iterdir()) == [
        "evaluation_00000.json", "evaluation_00004.json", "reference.json", MANIFEST]
    again = EvaluationStore.open(tmp_path / "s", analysis_key("screening", 3))
    assert again.read(range(-1, 6)) == {-1: reference, 0: done, 4: failed}
    assert done.ok and not failed.ok and math.isnan(Evaluation(index=1).seconds)  # no time given: NaN


def test_a_folder_of_another_analysis_is_refused_before_any_work(tmp_path):
    EvaluationStore.open(tmp_path, analysis_key("screening", 3)).write(Evaluation(index=0, values={"v": 1.0}))
    with pytest.raises(ModelError, match="holds the evaluations of another analysis"):
        EvaluationStore.open(tmp_path, analysis_key("screening", 4))
    # a stray file of another analysis in the right folder is refused when read, not mixed in
    (tmp_path / "evaluation_00001.json").write_text(json.dumps({"key": "other", "evaluation": {}}))
    with pytest.raises(ModelError, match="evaluation_00001.json: holds an evaluation of another analysis"):
        EvaluationStore.open(tmp_path, analysis_key("screening", 3)).read([0, 1])


def test_the_key_changes_with_any_input():
    assert analysis_key("a", 1, (0.5,)) == analysis_key("a", 1, (0.5,))
    assert len({analysis_key("a", 1, (0.5,)), analysis_key("a", 1, (0.6,)), analysis_key("b", 1, (0.5,))}) == 3
