"""The pursuit benchmark prints its rates, their ratios, and the vector env's step taken apart."""

import re

from animat.experiments.bench.vision import main


def test_the_pursuit_benchmark_prints_every_rate_and_the_vector_envs_parts(capsys):
    main(["--seconds", "1.0", "--rounds", "1", "--worlds", "4"])
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 13 and "1995" in lines[-1]
    for line in lines[:5]:
        value = float(re.search(r"\s([0-9.]+) (steps|frame-sets)/s", line).group(1))
        assert value > 0 and "x the physics" in line
    assert "the paper's loop" in lines[3]
    assert "4 worlds" in lines[5] and "x one env's step" in lines[5]
    whole = float(re.search(r"world: ([0-9]+) us", lines[6]).group(1))
    parts = [float(re.search(r"\s(-?[0-9]+) us", line).group(1)) for line in lines[7:12]]
    assert [p > 0 for p in parts[:4]] == [True] * 4  # physics, minds, geometry, cameras
    assert abs(sum(parts) - whole) <= 5  # the parts and the rest make up the step
