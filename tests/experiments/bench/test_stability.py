"""Stability as a property: the implicit step at 12.5 ms keeps the fish and the dolphin, in
both waters, finite and their tissue within 0.5-2 of its rest length under the sweep's random
and alternating drives (16 bodies, 10 s each), through the sweep's own loop
(:func:`animat.experiments.bench.stability.driven`); some bang-bang drives still break the
dolphin there (``docs/integrators.md``'s sweep), and the alternating drive breaks the explicit
fish."""

import numpy as np
import pytest

from animat.envs.bodies.dolphin import dolphin_body
from animat.envs.bodies.fish import fish_body
from animat.envs.physics.system import System, Water
from animat.experiments.bench.stability import driven, drives, noisy_start


@pytest.mark.parametrize("body_name", ["fish", "dolphin"])
@pytest.mark.parametrize("model", ["reactive", "resistive"])
def test_legal_drives_keep_the_body_sound_on_the_implicit_step_at_12_5_ms(body_name, model):
    body = fish_body() if body_name == "fish" else dolphin_body()
    system = System(body, Water(model=model), dt=0.0125, integrator="implicit")
    sweep = drives(16, np.random.default_rng(4))
    for name in ("random", "alternating"):
        sound, lows, highs = driven(system, sweep[name], noisy_start(body, 16), 10.0)
        assert sound.all(), (name, int(sound.sum()), float(lows.min()), float(highs.max()))


def test_a_body_that_goes_non_finite_is_not_sound():
    """The explicit fish under the alternating drive in the reactive water: the drive that
    blows the default up (its stiff tail, a step near its bound)."""
    body = fish_body()
    system = System(body, Water(), dt=0.05 / 40)
    sweep = drives(16, np.random.default_rng(4))
    sound, _, highs = driven(system, sweep["alternating"], noisy_start(body, 16), 5.0)
    assert not sound.all() and np.isinf(highs[~sound]).any()
