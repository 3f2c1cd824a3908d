"""Every shipped result (``results/``) re-scores to the figures it quotes: ``animat eval`` of
its folder, on the seeds of its ``eval.json``, gives the same metrics (to 1e-9), and writes
nothing into it. A change of the physics, a task or a controller that moves a quoted figure
fails here until the result is learned again."""

from pathlib import Path

import pytest

from animat.experiments.evaluate import evaluate
from animat.learners.storage.files import read_json

RESULTS = Path(__file__).resolve().parents[2] / "results"
# one of each kind in the default suite (about 40 s on 2 cores); the others, the second seeds
# and the learner comparisons' runs (results/compare/TASK/...), among the slow checks
DEFAULT = {"fish_basic_training", "fish_reach_behind", "fish_reach_switching_coordinate"}
FOLDERS = [pytest.param(p.parent, id=p.parent.relative_to(RESULTS).as_posix(),
                        marks=[] if p.parent.relative_to(RESULTS).as_posix() in DEFAULT
                        else [pytest.mark.slow])
           for p in sorted(RESULTS.rglob("eval.json"))]


def test_there_are_shipped_results():
    assert {"fish_basic_training", "fish_basic_training_seed1"} <= {
        f.values[0].name for f in FOLDERS}


def _re_scores_unchanged(folder, quoted: str, **played) -> None:
    """``animat eval`` of ``folder`` on the seeds of its ``quoted`` file, played as ``played``
    says, gives the figures it quotes and writes nothing into the folder."""
    before = {p: p.read_bytes() for p in folder.rglob("*") if p.is_file()}
    seeds = read_json(folder / quoted)["seeds"]
    result = evaluate(folder, seeds=seeds, **played)
    assert result["shipped"].startswith("the same as the shipped"), result["shipped"]
    assert {p: p.read_bytes() for p in folder.rglob("*") if p.is_file()} == before


@pytest.mark.parametrize("folder", FOLDERS)
def test_a_shipped_result_re_scores_to_what_it_quotes(folder):
    _re_scores_unchanged(folder, "eval.json")


POINT_STARTS = [pytest.param(p.parent, id=p.parent.relative_to(RESULTS).as_posix(),
                             marks=[pytest.mark.slow])
                for p in sorted(RESULTS.rglob("eval_point_start.json"))]


@pytest.mark.parametrize("folder", POINT_STARTS)
def test_a_shipped_result_from_its_documented_start_re_scores_to_what_it_quotes(folder):
    """The figure a shipped folder quotes from its task's documented start
    (``animat eval RUN --point-start``) is what its agent does from there."""
    _re_scores_unchanged(folder, "eval_point_start.json", point_start=True)
