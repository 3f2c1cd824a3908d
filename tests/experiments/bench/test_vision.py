"""The pursuit benchmark prints its rates, their ratios, and the vector env's step taken apart."""

import re

from animat.experiments.bench.vision import main


def test_the_pursuit_benchmark_prints_every_rate_and_the_vector_envs_parts(capsys):
    main(["--seconds", "1.0", "--rounds", "1", "--worlds", "4"])
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 12 and "1995" in lines[-1]
    for line in lines[:4]:
        value = float(re.search(r"\s([0-9.]+) (steps|frame-sets)/s", line).group(1))
        assert value > 0 and "x the physics" in line
    assert "4 worlds" in lines[4] and "x one env's step" in lines[4]
    whole = float(re.search(r"world: ([0-9]+) us", lines[5]).group(1))
    parts = [float(re.search(r"\s(-?[0-9]+) us", line).group(1)) for line in lines[6:11]]
    assert [p > 0 for p in parts[:4]] == [True] * 4  # physics, minds, geometry, cameras
    assert abs(sum(parts) - whole) <= 5  # the parts and the rest make up the step
