"""The simulator benchmark (``animat bench``) prints its rates and ratios, and its breakdown
(``animat bench --breakdown``) times every part of the step and the fused step."""

from tests.support.cli import animat


def test_the_benchmark_prints_every_configuration_and_the_ratios():
    out = animat("bench", "--seconds", "0.6", "--num-envs", "8").stdout
    assert "fish, 1 env" in out and "fish, native batch of 8" in out
    assert "ratio fish, 1 env / Swimmer-v5, 1 env" in out  # the bench extra is installed here
    assert "fish, resistive water, native batch of 8" in out
    assert "ratio fish, 1 env / fish, resistive water, 1 env" in out  # the default: reactive


def test_the_breakdown_times_every_part_and_the_fused_step():
    lines = animat("bench", "--breakdown").stdout.strip().splitlines()
    assert lines[0].startswith("part of a step") and len(lines) == 15
    assert "chunk of 32" in lines[0] and "chunk of 128" in lines[0]
    for line in lines[1:]:
        times = [float(v) for v in line.split()[-3:]]  # 1 body, chunks of 32 and 128
        assert all(t > 0 for t in times)
    assert lines[-3].startswith("fused step, reactive") and lines[-2].startswith("fused step")
    assert lines[-1].startswith("fused implicit step")
    assert [line.split(":")[0] for line in lines[9:12]] == ["implicit"] * 3
