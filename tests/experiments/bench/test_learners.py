"""``animat bench --learners``: the learners' env steps/s as they learn, beside the batch."""

import pytest

from animat.experiments.bench import learners
from tests.support.cli import animat


def test_each_learner_is_timed_as_it_learns_and_reported_against_the_batch():
    anchor = learners.batch_rate(0.2)
    rates = {label: learners.learner_rate(label, budget)
             for label, budget in (("annealing", 6400), ("PPO", 4096))}
    assert anchor > 1000 and all(rate > 100 for rate in rates.values())
    text = learners.report({learners.ANCHOR: anchor, **rates})
    assert "x anchor" in text.splitlines()[0] and "  1.00" in text.splitlines()[1]
    assert len(text.splitlines()) == 5  # the header, three rows, what was measured


def test_the_bench_takes_one_kind_at_a_time():
    result = animat("bench", "--breakdown", "--learners", check=False)
    assert result.returncode == 2 and "give one" in result.stderr
    result = animat("bench", "--seconds", "0", check=False)
    assert result.returncode == 2 and "--seconds must be > 0" in result.stderr


def test_pixel_rows_report_the_batch_the_learner_and_its_updates_share():
    anchor = learners.pixel_batch_rate(0.5)
    assert anchor > 0  # a rate, not a speed target: the bench prints the ratios
    text = learners.report({learners.ANCHOR: 1000.0, "PPO": 500.0, learners.PIXEL_ANCHOR: anchor,
                            learners.PIXEL_PPO: anchor / 2, learners.UPDATE_SHARE: 0.4})
    rows = text.splitlines()
    assert learners.PIXEL_ANCHOR in rows[6] and rows[6].endswith("  1.00")
    assert learners.PIXEL_PPO in rows[7] and rows[7].endswith("  0.50")
    assert rows[8].endswith("40%")


@pytest.mark.slow
def test_pixel_ppo_is_timed_from_what_the_learner_logs_of_its_rollouts_and_updates():
    rate, share = learners.pixel_ppo_rate()
    assert rate > 0 and 0.0 < share < 1.0
