"""The batch evaluator: a part-filled chunk plays on a narrower batch, with the same scores; a
candidate scored by its worst start states."""

import numpy as np
import pytest

from animat.learners.macro import MacroParams
from animat.learners.rollout import NARROW, BatchEvaluator, worst_mean


def test_a_part_filled_chunk_plays_on_a_narrow_batch_and_scores_the_same():
    evaluator = BatchEvaluator("Animat/FishSwim-v0", {"duration": 1.0}, num_envs=16, seed=3,
                               num_starts=4)  # a full batch of 64 rows
    rng = np.random.default_rng(0)
    actions = rng.uniform(-1, 1, (17, evaluator.steps, evaluator.action_size))
    full, full_metrics = evaluator.evaluate(actions)  # 64 rows, then 4 on a narrow batch
    assert set(evaluator._narrow) == {NARROW} and evaluator.env.num_envs == 64
    alone, alone_metrics = evaluator.evaluate(actions[16:])  # the last one by itself
    assert np.array_equal(alone, full[16:])  # bit for bit, whatever the batch's width
    assert all(np.array_equal(alone_metrics[k], full_metrics[k][16:]) for k in alone_metrics)
    inside, _ = evaluator.evaluate(np.concatenate([actions[16:], actions[:15]]))  # full batch
    assert inside[0] == alone[0]
    assert evaluator.env_steps == (17 + 1 + 16) * 4 * evaluator.steps  # the rows asked, only


def test_worst_share_scores_a_candidate_by_its_worst_starts_and_keeps_the_means():
    """With ``worst_share`` 0.5 the return is the mean of each candidate's 2 lowest of 4
    start returns (played singly, from the same seeds); the metrics stay the means."""
    kwargs = {"duration": 0.5}
    rng = np.random.default_rng(1)
    tail = BatchEvaluator("Animat/FishSwim-v0", kwargs, num_envs=3, seed=7, num_starts=4,
                          worst_share=0.5)
    actions = rng.uniform(-1, 1, (3, tail.steps, tail.action_size))
    returns, metrics = tail.evaluate(actions)
    singles = np.array([BatchEvaluator("Animat/FishSwim-v0", kwargs, num_envs=3, seed=7 + k,
                                       num_starts=1).evaluate(actions)[0] for k in range(4)])
    assert np.ptp(singles, axis=0).min() > 0  # the starts do differ
    np.testing.assert_allclose(returns, np.sort(singles, axis=0)[:2].mean(axis=0), rtol=1e-12)
    mean, mean_metrics = BatchEvaluator("Animat/FishSwim-v0", kwargs, num_envs=3, seed=7,
                                        num_starts=4).evaluate(actions)
    assert np.all(returns < mean)
    assert all(np.array_equal(metrics[k], mean_metrics[k]) for k in metrics)


def test_worst_mean_of_the_whole_share_is_the_plain_mean_bit_for_bit():
    rows = np.random.default_rng(2).normal(size=(5, 16))
    assert np.array_equal(worst_mean(rows, 1.0), rows.mean(axis=1))
    assert np.array_equal(worst_mean(rows, 0.01), rows.min(axis=1))
    np.testing.assert_allclose(worst_mean(rows, 0.25), np.sort(rows, axis=1)[:, :4].mean(1))


@pytest.mark.parametrize("share", [0, -0.5, 1.5, "half", None, float("nan")])
def test_a_worst_share_outside_0_to_1_is_refused_in_one_line(share):
    with pytest.raises(ValueError, match=r"^worst_share must be a number in \(0, 1\]") as err:
        MacroParams(repertoire="x.json", worst_share=share)
    assert "\n" not in str(err.value)
