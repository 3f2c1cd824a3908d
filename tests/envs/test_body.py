"""The fish body description: counts, units, faces, validation."""

import numpy as np
import pytest

from envs.body import CROSS, MUSCLE, ORDINARY, BodySpec
from envs.fish import fish_body
from envs.physics.forces import add_face_forces
from envs.physics.system import System


def test_counts_match_the_paper():
    body = fish_body()
    assert body.num_nodes == 23
    assert body.num_elements == 91
    assert body.num_muscles == 12
    assert body.num_actuators == 6
    assert np.count_nonzero(body.kinds == CROSS) == 46
    assert np.count_nonzero(body.kinds == ORDINARY) == 33
    assert sorted(np.bincount(body.actuator[body.kinds == MUSCLE])) == [2] * 6


def test_real_size_and_neutral_buoyancy():
    body = fish_body()
    assert body.length == pytest.approx(0.30)
    assert 0.3 < body.total_mass < 0.8  # kg, a 30 cm fish
    assert body.volumes.sum() * 1000.0 == pytest.approx(body.total_mass)


def test_stiffness_order_cross_ordinary_muscle():
    body = fish_body()
    cross, ordinary, muscle = (body.stiffness[body.kinds == k].min() for k in (CROSS, ORDINARY,
                                                                                 MUSCLE))
    assert cross > ordinary > muscle


def test_faces_point_outward():
    body = fish_body()
    p = body.rest_positions[body.faces]
    normals = np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 1])
    centres = (body.face_weights[:, :, None] * p).sum(axis=1)
    assert np.all(np.einsum("fk,fk->f", normals, centres * [0, 1, 1]) > 0)


def test_only_faces_moving_into_water_feel_force():
    system = System(fish_body())
    body = system.body
    x = body.rest_positions.copy()
    v = np.zeros_like(x)
    v[:, 1] = 0.5  # the whole fish moves to its left
    f = np.zeros_like(x)
    add_face_forces(x, v, body.faces, body.face_weights, system.face_mass, 500.0, 0.6,
                    np.inf, np.zeros(3), system.dt, f)
    assert f[:, 1].sum() < 0  # resisted
    left_nodes = body.rest_positions[:, 1] > 0
    assert np.all(f[~left_nodes & (body.rest_positions[:, 1] < 0), 1] == 0)  # lee side free


def test_bad_body_is_rejected_with_its_field_named():
    body = fish_body()
    fields = {name: getattr(body, name) for name in body.__dataclass_fields__}
    fields["masses"] = -fields["masses"]
    with pytest.raises(ValueError, match="masses"):
        BodySpec(**fields)
