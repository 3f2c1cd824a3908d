"""A second animal defined entirely as data, outside the library: an eel with its own node
and actuator counts, which swims in the fish envs via ``body=`` and registers as a body by
name (``register_body("eel", eel_body)``)."""

import numpy as np

from animat.envs.bodies.spec import CROSS, MUSCLE, ORDINARY, BodySpec, chain_sections

SIGNS = [(1, 1), (-1, 1), (-1, -1), (1, -1)]  # ring corners (y, z): ul, ur, lr, ll


def eel_body(sections: bool = True) -> BodySpec:
    """A 0.4 m, 3-ring eel: 14 nodes (nose, 3 rings of 4, tail tip), 50 elements, 8 muscles
    in 4 actuators (left and right, front and back segment), 16 faces, 2 fins; with
    ``sections``, 5 cross-sections for the reactive water (nose, rings, tail tip)."""
    stations = [(-0.1, 0.015), (-0.2, 0.012), (-0.3, 0.008)]
    nodes = [(0.0, 0.0, 0.0)] + [(x, sy * h, sz * h) for x, h in stations for sy, sz in SIGNS]
    nodes.append((-0.4, 0.0, 0.0))
    rings = [[1 + 4 * k + c for c in range(4)] for k in range(3)]
    elements, kinds, actuator = [], [], []

    def add(i, j, kind, act=-1):
        elements.append((i, j))
        kinds.append(kind)
        actuator.append(act)

    for c in range(4):
        add(0, rings[0][c], ORDINARY)
        add(rings[2][c], 13, ORDINARY)
    for ring in rings:
        for c in range(4):
            add(ring[c], ring[(c + 1) % 4], ORDINARY)
        add(ring[0], ring[2], CROSS)
        add(ring[1], ring[3], CROSS)
    for k, (front, back) in enumerate(zip(rings[:-1], rings[1:])):
        for c in range(4):
            left = c in (0, 3)
            add(front[c], back[c], MUSCLE, k if left else 2 + k)
            add(front[c], back[(c + 1) % 4], CROSS)
            add(front[(c + 1) % 4], back[c], CROSS)
    faces = [(0, rings[0][c], rings[0][(c + 1) % 4], rings[0][(c + 1) % 4]) for c in range(4)]
    faces += [(f[c], f[(c + 1) % 4], b[(c + 1) % 4], b[c])
              for f, b in zip(rings[:-1], rings[1:]) for c in range(4)]
    faces += [(rings[2][c], 13, rings[2][(c + 1) % 4], rings[2][(c + 1) % 4]) for c in range(4)]
    positions, faces = np.array(nodes), np.array(faces)
    p = positions[faces]
    normals = np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 1])
    inward = np.einsum("fk,fk->f", normals, p.mean(axis=1) * [0.0, 1.0, 1.0]) < 0
    faces[inward] = faces[inward, ::-1]
    weights = np.where(faces == np.roll(faces, 1, axis=1), 0.0, 1.0)
    weights /= weights.sum(axis=1, keepdims=True)
    masses = np.array([0.01] + [0.04] * 4 + [0.03] * 4 + [0.02] * 4 + [0.01])
    kinds = np.array(kinds)
    return BodySpec(
        name="eel", rest_positions=positions, masses=masses, volumes=masses / 1000.0,
        elements=np.array(elements), kinds=kinds,
        stiffness=np.where(kinds == MUSCLE, 150.0, 300.0), damping=np.full(len(kinds), 0.05),
        actuator=np.array(actuator),
        actuator_names=("left_front", "left_back", "right_front", "right_back"),
        max_contraction=0.4, faces=faces, face_weights=weights,
        fin_nodes=np.array([[1, 4], [2, 3]]), fin_areas=np.array([3e-4, 3e-4]),
        fin_names=("left", "right"), frame_front=np.array([0, 1, 2, 3, 4]),
        frame_back=np.array(rings[2]), frame_up=np.array([1, 2, 5, 6]),
        frame_down=np.array([3, 4, 7, 8]),
        **(chain_sections([0.0] + [x for x, _ in stations] + [-0.4], [[0]] + rings + [[13]],
                          [0.0] + [h for _, h in stations] + [0.004], 1.0) if sections else {}))

