"""The fish body description: counts, units, faces, validation."""

import numpy as np
import pytest

from animat.envs.bodies.fish import fish_body
from animat.envs.bodies.spec import CROSS, MUSCLE, ORDINARY, BodySpec
from animat.envs.physics.forces import add_face_forces
from animat.envs.physics.system import System, Water


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


@pytest.mark.parametrize("reaction", ["crossflow", "paper"])
def test_only_faces_moving_into_water_feel_the_reaction_force(reaction):
    system = System(fish_body(), Water(friction_coefficient=0.0, reaction=reaction))
    body = system.body
    x = body.rest_positions[:, :, None].copy()  # lane layout, one body
    v = np.zeros_like(x)
    v[:, 1] = 0.5  # the whole fish moves to its left
    f = np.zeros_like(x)
    c = system.kernel_args
    add_face_forces(x, v, c.faces, c.face_weights, c.face_mass, c.water, c.dt, f,
                    np.empty((len(c.faces), 4, 1)), np.zeros(1))
    assert f[:, 1].sum() < 0  # resisted
    left_nodes = body.rest_positions[:, 1] > 0
    lee = f[~left_nodes & (body.rest_positions[:, 1] < 0), 1]
    assert np.all(np.abs(lee) < 1e-12 * abs(f[:, 1].sum()))  # lee side free (to round-off)


def test_skin_friction_opposes_sliding_along_the_faces():
    """A body towed nose first: the cross-flow reaction charges only the nose's inclined faces,
    friction every face; both resist, and friction adds 0.5 rho C_f A U^2-scale drag."""
    drags = {}
    for friction in (0.0, 3.0):
        system = System(fish_body(), Water(friction_coefficient=friction))
        c = system.kernel_args
        x = system.body.rest_positions[:, :, None].copy()
        v = np.zeros_like(x)
        v[:, 0] = 0.3
        f = np.zeros_like(x)
        add_face_forces(x, v, c.faces, c.face_weights, c.face_mass, c.water, 1e-9, f,
                        np.empty((len(c.faces), 4, 1)), np.zeros(1))
        drags[friction] = -f[:, 0].sum()
    p = system.body.rest_positions[system.body.faces]
    wetted = 0.5 * np.linalg.norm(np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 1]), axis=1).sum()
    assert drags[0.0] > 0
    extra = drags[3.0] - drags[0.0]
    assert 0.8 * 3.0 * wetted * 0.3**2 < extra <= 3.0 * wetted * 0.3**2 * (1 + 1e-9)


def test_bad_body_is_rejected_with_its_field_named():
    body = fish_body()
    fields = {name: getattr(body, name) for name in body.__dataclass_fields__}
    fields["masses"] = -fields["masses"]
    with pytest.raises(ValueError, match="masses"):
        BodySpec(**fields)


def test_bad_section_axes_are_rejected_with_their_field_named():
    body = fish_body()
    fields = {name: getattr(body, name) for name in body.__dataclass_fields__}
    fields["section_up"] = fields["section_up"][:2]  # a row short
    with pytest.raises(ValueError, match="section_up and section_down"):
        BodySpec(**fields)
    fields["section_up"] = np.full_like(body.section_down, 99)  # no such node
    with pytest.raises(ValueError, match="section_up and section_down"):
        BodySpec(**fields)
    fields["section_up"], fields["section_down"] = body.section_up, None  # one of the two
    with pytest.raises(ValueError, match="give both section_up and section_down"):
        BodySpec(**fields)
