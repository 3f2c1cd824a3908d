"""The artificial dolphin: a :class:`~envs.bodies.spec.BodySpec` on the fish's topology, in SI
units.

The paper's dolphin (Section 4.2) is a marine mammal: it swims by beating horizontal tail
flukes up and down, and it breathes air. This body keeps the fish's 23 nodes and 91 Voigt
elements (:mod:`animat.envs.bodies.fish`), re-shaped and re-muscled:

* **Shape** (model units of 26 per body length, as the fish): a rostrum, a melon, the girth
  behind the flippers, a tall, thin tail stock (peduncle), and the two caudal tips placed left
  and right of the body axis instead of above and below, so that the four caudal faces form
  horizontal flukes spanning 0.24 body lengths (a bottlenose's 0.6 m on 2.5 m).
* **Muscles** (12, in 6 actuators): in the middle and back segments the two upper corner
  muscles of a segment form its dorsal actuator and the two lower ones its ventral actuator:
  alternating dorsal and ventral contraction, the back lagging the middle, beats the flukes up
  and down (dorsoventral undulation). The front segment's muscles stay lateral (left pair,
  right pair), the anterior flexion a dolphin turns with; pitch and roll also come from the
  pectoral fins (flippers), as for the fish.
* **Scale**: 2.5 m long. Every force of the fish is scaled so that the dolphin is the fish
  made 8.3 times bigger with its time unchanged (``length`` s: masses and displaced volumes as
  ``s^3``, stiffness and damping as ``s^3``, areas as ``s^2``): the body's own modes, and the
  integrator's stable step, stay those of the fish. Then the muscles are made ``muscle_gain``
  times stronger than that (a dolphin is a sprinter: up to 3 body lengths per second), and
  the elements that carry their load with them.
* **Buoyancy**: the body's tissue is denser than water and its lungs (``lung_share`` of its
  volume at the surface, in the chest) hold air that Boyle's law compresses with depth
  (:func:`animat.envs.physics.forces.compressed`). The level body is neutral with its centre
  of mass at ``neutral_depth`` (each node's volume is its own water's there, before a small
  share moves from the lower nodes to the upper ones to keep it upright): released there at
  rest the dolphin stays; above it, it is buoyant and floats up to the surface, as a dolphin
  at rest does; below it, it sinks. The lungs' pressure head is that of Water's defaults
  (101325 Pa, 9.81 m/s^2); with other values the neutral depth moves.

Total mass 170 kg (the hull's volume of water of 1000 kg/m^3).
"""

from __future__ import annotations

import numpy as np

from .fish import (
    _CROSS,
    _DAMPING,
    _ORDINARY,
    _RING_SIGNS,
    _STIFFNESS,
    HOOP_STIFFNESS,
    MODEL_LENGTH_UNITS,
    WATER_DENSITY,
    _is_hoop,
    _pairs,
    ring_faces,
)
from .spec import CROSS, MUSCLE, NOSE_PART, ORDINARY, TAIL_PART, BodySpec, chain_sections

FISH_LENGTH = 0.30  # m: the fish whose forces the dolphin scales
PRESSURE_HEAD = 101325.0 / (WATER_DENSITY * 9.81)  # m of water per atmosphere

# Rings (ul, ur, lr, ll) by station: (x, half width along y, half height along z), model units.
STATIONS = [(-4.0, 1.3, 1.45), (-9.0, 1.85, 2.1), (-15.0, 1.6, 1.9), (-20.5, 0.6, 1.1),
            (-23.0, 0.35, 0.6)]
FLUKE_TIP = (-26.0, 3.1)  # (x, |y|) of the caudal tips, model units
STATION_MASSES = (1.5, 7.0, 11.0, 7.0, 1.6, 1.0, 0.9)  # nose, five rings, each fluke tip

ACTUATOR_NAMES = ("dorsal_middle", "dorsal_back", "ventral_middle", "ventral_back",
                  "left_front", "right_front")
DORSAL_MIDDLE, DORSAL_BACK, VENTRAL_MIDDLE, VENTRAL_BACK, LEFT_FRONT, RIGHT_FRONT = range(6)
_MUSCLES = {  # actuator index -> corner edges (ring nodes ul, ur, lr, ll at 1+4k .. 4+4k)
    LEFT_FRONT: [(1, 5), (4, 8)], RIGHT_FRONT: [(2, 6), (3, 7)],
    DORSAL_MIDDLE: [(5, 9), (6, 10)], VENTRAL_MIDDLE: [(7, 11), (8, 12)],
    DORSAL_BACK: [(9, 13), (10, 14)], VENTRAL_BACK: [(11, 15), (12, 16)],
}
LEFT_TIP, RIGHT_TIP = 21, 22
NOSE_FACES = (0, 1, 2, 3)  # the head: rostrum and melon, in front of the first ring
TAIL_FACES = (16, 17, 18, 19, 20, 21, 22, 23)  # the tail stock's quads and the flukes


# The dolphin undulates up and down: its sections carry water for vertical motion, across their
# half widths (the rings', the flukes' half span; a thin tall tail stock carries little).
SECTION_HALF_EXTENTS = [0.0] + [w for _, w, _ in STATIONS] + [FLUKE_TIP[1]]


def dolphin_sections(scale: float) -> dict[str, np.ndarray]:
    """The dolphin's cross-section fields of :class:`BodySpec` (``section_*``), m and m^2,
    with its plane of undulation the vertical one: each section's axis across it is its own
    left (a ring's left corners less its right ones, the nose its first ring's, the flukes'
    left tip less the right: so it stays defined when the tail bends sideways, where the
    front's left would line up with the tail and flip the tail's normal)."""
    groups = [[0]] + [list(range(1 + 4 * k, 5 + 4 * k)) for k in range(len(STATIONS))]
    stations = [0.0] + [x for x, _, _ in STATIONS] + [FLUKE_TIP[0]]
    sections = chain_sections(stations, groups + [[LEFT_TIP, RIGHT_TIP]], SECTION_HALF_EXTENTS,
                              scale)
    rings = [0] + list(range(len(STATIONS)))  # the nose takes its first ring's
    left = [[1 + 4 * k, 4 + 4 * k] for k in rings] + [[LEFT_TIP, LEFT_TIP]]
    right = [[2 + 4 * k, 3 + 4 * k] for k in rings] + [[RIGHT_TIP, RIGHT_TIP]]
    return {**sections, "section_up": np.array(left), "section_down": np.array(right)}


def _tail_pairs(text: str) -> list[tuple[int, int]]:
    """The fish's element list with its caudal tips re-attached: the fish's upper tip (21)
    joins the upper ring nodes 17, 18; the dolphin's left tip joins the left ones, 17 and 20
    (swap 18 and 20 in every element touching a tip)."""
    swap = {18: 20, 20: 18}
    return [(swap.get(i, i), swap.get(j, j)) if {i, j} & {LEFT_TIP, RIGHT_TIP} else (i, j)
            for i, j in _pairs(text)]


def rest_positions_units() -> np.ndarray:
    """(23, 3) rest shape in model units (x forward, y left, z up)."""
    nodes = [(0.0, 0.0, -0.3)]  # the rostrum, a little below the axis
    for x, half_y, half_z in STATIONS:
        nodes += [(x, sy * half_y, sz * half_z) for sy, sz in _RING_SIGNS]
    x, y = FLUKE_TIP
    nodes += [(x, y, 0.0), (x, -y, 0.0)]
    return np.array(nodes)


def _faces() -> tuple[np.ndarray, np.ndarray]:
    """24 faces: 4 nose triangles, 16 quads between rings, the flukes' upper and lower faces
    and their two edge triangles; corners ordered so that each normal points outward."""
    faces = ring_faces(len(STATIONS))
    faces += [(17, LEFT_TIP, RIGHT_TIP, 18), (20, LEFT_TIP, RIGHT_TIP, 19),
              (17, 20, LEFT_TIP, LEFT_TIP), (18, 19, RIGHT_TIP, RIGHT_TIP)]
    faces = np.array(faces)
    p = rest_positions_units()[faces]
    normals = np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 1])
    away = p.mean(axis=1) * np.array([0.0, 1.0, 1.0])
    away[-4:-2] = [[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]]  # the flukes: up and down
    inward = np.einsum("fk,fk->f", normals, away) < 0
    faces[inward] = faces[inward, ::-1]
    weights = np.where(faces == np.roll(faces, 1, axis=1), 0.0, 1.0)
    return faces, weights / weights.sum(axis=1, keepdims=True)


def hull_volume(scale: float) -> float:
    """Volume of the hull (nose pyramid, ring-to-ring frusta of rectangles), m^3."""
    xs = [0.0] + [x for x, _, _ in STATIONS]
    areas = [0.0] + [4.0 * hy * hz for _, hy, hz in STATIONS]
    total = sum((xs[k] - xs[k + 1]) / 3.0 * (areas[k] + areas[k + 1]
                                             + np.sqrt(areas[k] * areas[k + 1]))
                for k in range(len(xs) - 1))
    return total * scale**3


def _masses(total: float) -> np.ndarray:
    nose, *rings, tip = STATION_MASSES
    units = np.array([nose] + [m for m in rings for _ in range(4)] + [tip, tip])
    return total * units / units.sum()


def _lungs(volume: float, lung_share: float) -> np.ndarray:
    """(23,) air per node at the surface, m^3: in the chest (the upper nodes of rings 0 and 1,
    behind the melon and above the flippers)."""
    lungs = np.zeros(23)
    chest = [1, 2, 5, 6]
    lungs[chest] = lung_share * volume / len(chest)
    return lungs


def _lift_upper(volumes: np.ndarray, share: float) -> np.ndarray:
    """Move ``share`` of each lower ring node's volume (lr, ll) to the upper node above it
    (ur, ul): a righting moment, as for the fish."""
    out = volumes.copy()
    for ring in range(len(STATIONS)):
        ul, ur, lr, ll = 1 + 4 * ring, 2 + 4 * ring, 3 + 4 * ring, 4 + 4 * ring
        for lower, upper in ((lr, ur), (ll, ul)):
            moved = share * volumes[lower]
            out[lower] -= moved
            out[upper] += moved
    return out


def dolphin_body(length: float = 2.5, muscle_gain: float = 3.0, max_contraction: float = 0.5,
                 lung_share: float = 0.05, neutral_depth: float = 3.0,
                 buoyancy_lift: float = 0.05, fin_area: float = 1e-3, sections: bool = True
                 ) -> BodySpec:
    """The artificial dolphin.

    Args:
        length: nose to fluke tips, m.
        muscle_gain: muscle stiffness over the scaled fish's (and the elements loaded with
            them: the cross struts and surface edges, by ``sqrt(muscle_gain)``).
        max_contraction: muscle rest-length shortening at full activation (fraction).
        lung_share: air in the lungs at the surface, as a share of the body's volume.
        neutral_depth: depth of the centre of mass at which every node of the level rest shape
            is neutrally buoyant, m (the depth the dolphin's tasks start at).
        buoyancy_lift: share of each lower node's tissue volume moved to the node above it
            (the centre of buoyancy above the centre of mass: the dolphin floats upright).
        fin_area: each flipper's area for the 0.30 m fish, m^2 (scaled by ``s^2``).
        sections: give the body its cross-sections (:func:`dolphin_sections`) for the
            reactive water.
    """
    if not (length > 0 and muscle_gain > 0 and lung_share >= 0 and neutral_depth >= 0):
        raise ValueError("dolphin_body needs length > 0, muscle_gain > 0, lung_share >= 0 and "
                         "neutral_depth >= 0")
    scale = length / MODEL_LENGTH_UNITS
    s = length / FISH_LENGTH
    volume = hull_volume(scale)
    masses = _masses(WATER_DENSITY * volume)
    lungs = _lungs(volume, lung_share)
    rest = rest_positions_units() * scale
    depths = neutral_depth - (rest[:, 2] - masses @ rest[:, 2] / masses.sum())
    tissue = masses / WATER_DENSITY - lungs / (1.0 + depths / PRESSURE_HEAD)
    tissue = _lift_upper(tissue, buoyancy_lift)
    muscles = [(pair, act) for act, pairs in sorted(_MUSCLES.items()) for pair in pairs]
    passive = _tail_pairs(_CROSS) + _tail_pairs(_ORDINARY)
    elements = [p for p, _ in muscles] + passive
    kinds = [MUSCLE] * len(muscles) + [CROSS] * len(_pairs(_CROSS)) + [ORDINARY] * len(
        _pairs(_ORDINARY))
    passive_gain = np.sqrt(muscle_gain)
    stiffness = [(muscle_gain if k == MUSCLE else passive_gain)
                 * (HOOP_STIFFNESS if _is_hoop(pair) else _STIFFNESS[k])
                 for pair, k in zip(elements, kinds)]
    damping = [(muscle_gain if k == MUSCLE else passive_gain) * _DAMPING[k] for k in kinds]
    faces, weights = _faces()
    parts = np.zeros(len(faces), dtype=np.int64)
    parts[list(NOSE_FACES)], parts[list(TAIL_FACES)] = NOSE_PART, TAIL_PART
    return BodySpec(
        name="dolphin",
        rest_positions=rest,
        masses=masses, volumes=tissue, lung_volumes=lungs,
        elements=np.array(elements), kinds=np.array(kinds),
        stiffness=s**3 * np.array(stiffness), damping=s**3 * np.array(damping),
        actuator=np.array([a for _, a in muscles] + [-1] * len(passive)),
        actuator_names=ACTUATOR_NAMES, max_contraction=max_contraction,
        faces=faces, face_weights=weights,
        fin_nodes=np.array([[1, 4, 5, 8], [2, 3, 6, 7]]),
        fin_areas=np.full(2, fin_area * s**2), fin_names=("left", "right"),
        frame_front=np.array([0, 1, 2, 3, 4]), frame_back=np.array([9, 10, 11, 12]),
        frame_up=np.array([1, 2, 5, 6, 9, 10]), frame_down=np.array([3, 4, 7, 8, 11, 12]),
        length=length, face_parts=parts, **(dolphin_sections(scale) if sections else {}),
    )
