"""The batch evaluator: a part-filled chunk plays on a narrower batch, with the same scores."""

import numpy as np

from animat.learners.rollout import NARROW, BatchEvaluator


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
