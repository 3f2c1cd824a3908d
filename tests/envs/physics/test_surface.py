"""The water surface: in air a body is ballistic, at the surface the water's grip and lift
fade in smoothly with how much of each face and node is under, and a buoyant body comes to
rest floating at the surface."""

from dataclasses import replace

import numpy as np

from animat.envs.bodies.fish import fish_body
from animat.envs.physics.forces import sphere_submerged, wet_fraction
from animat.envs.physics.integrator import step_batch
from animat.envs.physics.system import System, Water

G = 9.81


def _com(body, x):
    return body.masses @ x[0] / body.total_mass


def test_a_body_thrown_in_air_follows_a_parabola():
    """No water force reaches above the surface: with the (small) air drag off, the centre of
    mass follows symplectic Euler's parabola to round-off; with it on, within 0.3%."""
    for air, tolerance in ((0.0, 1e-9), (Water().air_coefficient, 3e-3)):
        water = Water(surface_z=-5.0, air_coefficient=air, air_friction_coefficient=0.0)
        system = System(fish_body(), water)
        x = system.body.rest_positions[None].copy()
        v = np.tile([1.0, 0.0, 2.0], (1, system.body.num_nodes, 1))
        start, h = _com(system.body, x), system.dt
        steps = int(round(0.4 / h))
        step_batch(x, v, np.zeros((1, 6)), np.zeros((1, 6)), np.zeros((1, 2)), steps,
                   system.kernel_args)
        moved = _com(system.body, x) - start
        t = steps * h
        rise = 2.0 * t - 0.5 * G * h**2 * steps * (steps + 1)  # the scheme's discrete parabola
        assert abs(moved[0] - 1.0 * t) <= tolerance * t
        assert abs(moved[2] - rise) <= tolerance * (abs(rise) + 2.0 * t)
        assert abs(moved[1]) < 1e-9


def test_buoyancy_and_the_water_grip_fade_in_smoothly_across_the_surface():
    """Lowering the fish through the surface in 1 mm steps, its total lift never grows by more
    than 3% of the whole per step (measured 1.6%); with every node's volume going under at
    once, as before, it jumped by 25% at one step."""
    body = fish_body()
    radii = np.maximum((0.75 * body.volumes / np.pi) ** (1 / 3), 1e-6)
    lifts = []
    for depth in np.arange(-0.1, 0.1, 0.001):  # centre of mass from 10 cm above to below
        z = body.rest_positions[:, 2] - depth
        lifts.append(sum(v * sphere_submerged(zi, r, 0.0) for v, zi, r in
                         zip(body.volumes, z, radii)))
    lifts = np.array(lifts) / body.volumes.sum()
    assert lifts[0] == 0.0 and abs(lifts[-1] - 1.0) < 1e-12 and np.all(np.diff(lifts) >= 0)
    assert np.diff(lifts).max() < 0.03
    assert wet_fraction(-0.1, 0.1, 0.0) == 0.5 and wet_fraction(0.1, 0.2, 0.0) == 0.0
    assert wet_fraction(-0.2, -0.1, 0.0) == 1.0 and wet_fraction(0.0, 0.0, np.inf) == 1.0


def test_a_buoyant_body_released_under_water_or_dropped_from_above_floats_at_the_surface():
    """A fish 3% lighter than the water it displaces (lungs, say): released at rest 20 cm down
    it rises; dropped from 20 cm above it falls, plunges and comes back up. Both settle at the
    same floating height (measured: -4.72 and -4.71 cm for the centre of mass, bobbing by
    1 mm), with the lift equal to the weight and part of the body out of the water."""
    base = fish_body()
    body = replace(base, volumes=base.volumes * 1.03)
    system = System(body, Water(surface_z=0.0))
    radii = np.maximum((0.75 * body.volumes / np.pi) ** (1 / 3), 1e-6)
    steps = int(round(0.05 / system.dt))
    rests = []
    for offset in (-0.2, 0.2):
        x = body.rest_positions[None].copy()
        x[0, :, 2] += offset - _com(body, x)[2]
        v = np.zeros_like(x)
        heights, lifts = [], []
        for _ in range(400):  # 20 s
            step_batch(x, v, np.zeros((1, 6)), np.zeros((1, 6)), np.zeros((1, 2)), steps,
                       system.kernel_args)
            heights.append(_com(body, x)[2])
            lifts.append(1000.0 * sum(vol * sphere_submerged(z, r, 0.0) for vol, z, r in
                                      zip(body.volumes, x[0, :, 2], radii)))
        heights = np.array(heights)
        if offset > 0:
            assert heights.min() < -0.1  # it plunged under
        assert heights[-100:].std() < 3e-3  # settled (the last 5 s)
        lift = np.mean(lifts[-40:]) / body.total_mass  # over the last 2 s
        assert abs(lift - 1.0) < 5e-3 and lift < 1.02  # floating: not all of it under
        rests.append(heights[-100:].mean())
    assert -0.07 < rests[0] < 0.0 and abs(rests[0] - rests[1]) < 5e-3
