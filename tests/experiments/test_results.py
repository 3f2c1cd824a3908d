"""Every shipped result (``results/``) re-scores to the figures it quotes: ``animat eval`` of
its folder, on the seeds of its ``eval.json``, gives the same metrics (to 1e-9), and writes
nothing into it. A change of the physics, a task or a controller that moves a quoted figure
fails here until the result is learned again."""

from pathlib import Path

import pytest

from animat.experiments.evaluate import evaluate
from animat.learners.storage.files import read_json

RESULTS = Path(__file__).resolve().parents[2] / "results"
FOLDERS = sorted(p.parent for p in RESULTS.glob("*/eval.json"))


def test_there_are_shipped_results():
    assert {"fish_basic_training", "fish_basic_training_seed1"} <= {f.name for f in FOLDERS}


@pytest.mark.parametrize("folder", FOLDERS, ids=[f.name for f in FOLDERS])
def test_a_shipped_result_re_scores_to_what_it_quotes(folder):
    before = {p: p.read_bytes() for p in folder.rglob("*") if p.is_file()}
    seeds = read_json(folder / "eval.json")["seeds"]
    result = evaluate(folder, seeds=seeds)
    assert result["shipped"].startswith("the same as the shipped"), result["shipped"]
    assert {p: p.read_bytes() for p in folder.rglob("*") if p.is_file()} == before
