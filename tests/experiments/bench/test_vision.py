"""The pursuit benchmark prints its four rates and their ratios to the physics."""

import re

from animat.experiments.bench.vision import main


def test_the_pursuit_benchmark_prints_every_rate(capsys):
    main(["--seconds", "0.8", "--rounds", "1"])
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 5 and "1995" in lines[-1]
    for line in lines[:4]:
        value = float(re.search(r"\s([0-9.]+) (steps|frame-sets)/s", line).group(1))
        assert value > 0 and "x the physics" in line
