"""The measurements of a state: over Numba's threads (from PARALLEL_BODIES bodies) they give
the numbers of the one-body-after-another kernels, bit for bit."""

import numpy as np
import pytest

from animat.envs.bodies import fish_body
from animat.envs.physics import observe

BODY = fish_body()


def _bodies(count: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(count)
    x = BODY.rest_positions[None] + 0.02 * rng.standard_normal((count, len(BODY.masses), 3))
    return x, rng.standard_normal(x.shape)


@pytest.mark.parametrize("count", [observe.PARALLEL_BODIES, 257])
def test_threaded_measurements_match_the_serial_ones_bit_for_bit(count):
    x, v = _bodies(count)
    frame_nodes = (BODY.frame_front, BODY.frame_back, BODY.frame_up, BODY.frame_down)
    com, com_vel, frames = observe.body_state(x, v, BODY.masses, *frame_nodes)
    rows = [observe.body_state(x[b:b + 1], v[b:b + 1], BODY.masses, *frame_nodes)
            for b in range(count)]  # a batch of one runs the serial kernel
    for threaded, serial in zip((com, com_vel, frames), zip(*rows)):
        assert np.array_equal(threaded, np.concatenate(serial))
    linear, angular = observe.momenta(x, v, BODY.masses, com)
    serial = [observe.momenta(x[b:b + 1], v[b:b + 1], BODY.masses, com[b:b + 1])
              for b in range(count)]
    assert np.array_equal(linear, np.concatenate([s[0] for s in serial]))
    assert np.array_equal(angular, np.concatenate([s[1] for s in serial]))
    activation = np.linspace(0.0, 1.0, 6 * count).reshape(count, 6)
    out = np.empty((count, 6 * len(BODY.masses) + 12), np.float32)
    observe.proprioception(x, v, activation, com, com_vel, frames, BODY.length, 10.0, out)
    row = np.empty((1, out.shape[1]), np.float32)
    for b in range(count):
        observe.proprioception(x[b:b + 1], v[b:b + 1], activation[b:b + 1], com[b:b + 1],
                               com_vel[b:b + 1], frames[b:b + 1], BODY.length, 10.0, row)
        assert np.array_equal(out[b], row[0])
    assert np.abs(angular).max() > 0.0 and np.isfinite(out).all()
