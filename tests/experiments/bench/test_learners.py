"""``animat bench --learners``: the learners' env steps/s as they learn, beside the batch."""

from animat.experiments.bench import learners
from tests.experiments.test_cli import animat


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
