"""The artificial fish of Tu & Terzopoulos (1994), as a :class:`~envs.bodies.spec.BodySpec` in SI
units.

Topology (23 nodes, 91 elements, 12 muscles in 6 actuators) is that of Tu & Terzopoulos,
"Artificial fishes" (1994) and X. Tu's thesis (1996), as the paper fixes it. The model's 26
units are scaled to a 0.30 m fish. The total mass is the hull's volume of water (0.51 kg for
0.30 m, like a stocky carp or trout), shared among the nodes in the data sheet's proportions;
each node displaces its own mass of water, so the fish is neutrally buoyant (with a small
righting lift on the upper nodes). Stiffnesses keep the data sheet's order (cross > ordinary >
muscle), with the ring edges (hoops) stiffest, so that every passive element stays within
0.79-1.23 of its rest length under random actions (``tests/envs/physics/test_tissue.py``). The
stiffest mode sets the integrator's step bound (:func:`animat.envs.physics.system.stable_step`,
1.69 ms).
"""

from __future__ import annotations

import numpy as np

from .spec import CROSS, MUSCLE, ORDINARY, BodySpec, chain_sections

MODEL_LENGTH_UNITS = 26.0
WATER_DENSITY = 1000.0  # kg/m^3

# Rings of four nodes (upper-left, upper-right, lower-right, lower-left), by station.
_STATIONS = [  # (x, half size of the square cross-section), model units
    (-5.0, 2.0), (-10.0, 3.0), (-15.0, 2.0), (-20.0, 1.0), (-22.0, 0.8),
]
_RING_SIGNS = [(1, 1), (-1, 1), (-1, -1), (1, -1)]  # (y, z) signs: ul, ur, lr, ll

_MUSCLES = {  # actuator index -> node pairs (left: +y side)
    0: [(1, 5), (4, 8)], 1: [(5, 9), (8, 12)], 2: [(9, 13), (12, 16)],
    3: [(2, 6), (3, 7)], 4: [(6, 10), (7, 11)], 5: [(10, 14), (11, 15)],
}
ACTUATOR_NAMES = ("left_front", "left_middle", "left_back",
                  "right_front", "right_middle", "right_back")
_CROSS = """1-3 1-6 1-8 2-4 2-5 2-7 3-6 3-8 4-5 4-7 5-7 5-10 5-12 6-8 6-9 6-11 7-10 7-12 8-9 8-11
9-11 9-14 9-16 10-12 10-13 10-15 11-14 11-16 12-13 12-15 13-15 13-18 13-20 14-16 14-17 14-19
15-18 15-20 16-17 16-19 17-19 17-22 18-20 18-22 19-21 20-21"""
_ORDINARY = """0-1 0-2 0-3 0-4 1-2 1-4 2-3 3-4 5-6 5-8 6-7 7-8 9-10 9-12 10-11 11-12 13-14 13-16
13-17 14-15 14-18 15-16 15-19 16-20 17-18 17-20 17-21 18-19 18-21 19-20 19-22 20-22 21-22"""

# Stiffness (N/m) and damping (N s/m) per kind, for the 0.30 m fish.
_STIFFNESS = {CROSS: 600.0, ORDINARY: 450.0, MUSCLE: 350.0}
HOOP_STIFFNESS = 1200.0  # N/m: the four edges of each ring, which keep its cross-section
_DAMPING = {CROSS: 0.2, ORDINARY: 0.15, MUSCLE: 0.15}


def _pairs(text: str) -> list[tuple[int, int]]:
    return [tuple(int(k) for k in token.split("-")) for token in text.split()]  # type: ignore[misc]


def _rest_positions_units() -> np.ndarray:
    nodes = [(0.0, 0.0, 0.0)]
    for x, half in _STATIONS:
        nodes += [(x, sy * half, sz * half) for sy, sz in _RING_SIGNS]
    nodes += [(-26.0, 0.0, 3.0), (-26.0, 0.0, -3.0)]  # caudal fin tips (top, bottom)
    return np.array(nodes)


# Mass per node by station (nose, the five rings, the caudal-fin tips), in the data sheet's
# units: most of the mass in the middle of the body, a light peduncle and tail.
STATION_MASSES = (1.1, 6.6, 11.0, 6.6, 1.1, 1.1, 1.1)


def _node_masses(total: float, station_masses: tuple[float, ...]) -> np.ndarray:
    """(23,) nodal masses, kg, in the data sheet's proportions, summing to ``total``; the
    caudal-fin tips get the peduncle ring's share (the sheet's 0.165 would make them the
    stiffest, fastest-vibrating part of the body and set the step of the whole simulation)."""
    nose, *rings, tail = station_masses
    units = np.array([nose] + [m for m in rings for _ in range(4)] + [tail, tail])
    return total * units / units.sum()


def _node_volumes(masses: np.ndarray, buoyancy_lift: float) -> np.ndarray:
    """(23,) displaced volume per node, m^3: each node neutrally buoyant, then a fraction
    ``buoyancy_lift`` of each lower node's volume moved to the upper node above it, so the
    centre of buoyancy sits above the centre of mass and the fish floats upright."""
    volumes = masses / WATER_DENSITY
    upper = np.array([False] + [sz > 0 for _ in _STATIONS for _, sz in _RING_SIGNS] + [True, False])
    lower = np.array([False] + [sz < 0 for _ in _STATIONS for _, sz in _RING_SIGNS] + [False, True])
    shift = buoyancy_lift * volumes
    return volumes + np.where(upper, shift, 0.0) - np.where(lower, shift, 0.0)


def _body_volume(scale: float) -> float:
    """Volume of the body's hull (nose pyramid and ring-to-ring frusta), m^3."""
    xs = [0.0] + [x for x, _ in _STATIONS]
    areas = [0.0] + [(2 * h) ** 2 for _, h in _STATIONS]
    total = 0.0
    for k in range(len(xs) - 1):
        a0, a1, dx = areas[k], areas[k + 1], xs[k] - xs[k + 1]
        total += dx / 3.0 * (a0 + a1 + np.sqrt(a0 * a1))
    return total * scale**3


def _is_hoop(pair: tuple[int, int]) -> bool:
    """Whether an element is an edge of one ring (both nodes in the same ring of four)."""
    i, j = pair
    return 1 <= i <= 20 and 1 <= j <= 20 and (i - 1) // 4 == (j - 1) // 4


def _outward(faces: np.ndarray, positions: np.ndarray) -> np.ndarray:
    """Reorder each face's corners so that its normal points away from the body's axis."""
    p = positions[faces]
    normals = np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 1])
    centres = p.mean(axis=1)
    away = centres * np.array([0.0, 1.0, 1.0])
    inward = np.einsum("fk,fk->f", normals, away) < 0
    faces[inward] = faces[inward, ::-1]
    return faces


def ring_faces(stations: int) -> list[tuple[int, int, int, int]]:
    """The faces of a nose (node 0) and ``stations`` rings of four (nodes 1 + 4k ..): 4 nose
    triangles (a repeated corner), then 4 side quads between each pair of rings."""
    rings = [list(range(1 + 4 * k, 5 + 4 * k)) for k in range(stations)]
    faces = [(0, rings[0][s], rings[0][(s + 1) % 4], rings[0][(s + 1) % 4]) for s in range(4)]
    for front, back in zip(rings[:-1], rings[1:]):
        for s in range(4):
            t = (s + 1) % 4
            faces.append((front[s], front[t], back[t], back[s]))
    return faces


def _faces() -> tuple[np.ndarray, np.ndarray]:
    """Hydrodynamic faces: 4 nose triangles, 16 side quads between rings, 4 caudal-fin faces."""
    faces = ring_faces(len(_STATIONS))
    faces += [(17, 21, 22, 20), (18, 21, 22, 19), (17, 18, 21, 21), (20, 19, 22, 22)]
    faces = _outward(np.array(faces), _rest_positions_units())
    weights = np.where(faces == np.roll(faces, 1, axis=1), 0.0, 1.0)
    weights /= weights.sum(axis=1, keepdims=True)
    return faces, weights


# The cross-sections the water's reactive force acts on (the nose, the five rings, the caudal
# fin's trailing edge), with their half-extents across sideways motion (the half depth) in
# model units: the square rings' half sides; at the last ring the caudal fin begins (half its
# depth half-way to the tips, 1.1); the trailing edge is the fin's full span (the tips at +-3).
# The fish undulates sideways, and the reactive force acts in that plane only (Lighthill's
# theory of lateral undulation): with added mass for vertical motion too, the body's Munk
# moment, which nothing at the tail balances in pitch (the caudal fin is vertical), pitches
# the swimming fish over into a loop within seconds.
SECTION_HALF_EXTENTS = [0.0] + [h for _, h in _STATIONS[:-1]] + [1.1, 3.0]


def fish_sections(scale: float) -> dict[str, np.ndarray]:
    """The fish's cross-section fields of :class:`BodySpec` (``section_*``), m and m^2."""
    groups = [[0]] + [list(range(1 + 4 * k, 5 + 4 * k)) for k in range(len(_STATIONS))]
    stations = [0.0] + [x for x, _ in _STATIONS] + [-MODEL_LENGTH_UNITS]
    return chain_sections(stations, groups + [[21, 22]], SECTION_HALF_EXTENTS, scale)


def fish_body(length: float = 0.30, max_contraction: float = 0.5,
              fin_area: float = 1e-3, buoyancy_lift: float = 0.05,
              stiffness_scale: float = 1.0, station_masses: tuple[float, ...] = STATION_MASSES
              ) -> BodySpec:
    """The artificial fish as a body description.

    Args:
        length: body length nose to tail tip, m.
        max_contraction: muscle rest-length shortening at full activation (fraction).
        fin_area: area of each pectoral fin, m^2.
        buoyancy_lift: fraction of each node's volume moved from lower to upper nodes
            (raises the centre of buoyancy above the centre of mass: righting moment).
    """
    scale = length / MODEL_LENGTH_UNITS
    masses = _node_masses(WATER_DENSITY * _body_volume(scale) * 1.004,  # hull + caudal fin
                          station_masses)
    volumes = _node_volumes(masses, buoyancy_lift)

    muscles = [(pair, act) for act, pairs in _MUSCLES.items() for pair in pairs]
    elements = ([p for p, _ in muscles] + _pairs(_CROSS) + _pairs(_ORDINARY))
    kinds = [MUSCLE] * len(muscles) + [CROSS] * len(_pairs(_CROSS)) + [ORDINARY] * len(
        _pairs(_ORDINARY))
    actuator = [a for _, a in muscles] + [-1] * (len(elements) - len(muscles))
    faces, weights = _faces()
    return BodySpec(
        name="fish",
        rest_positions=_rest_positions_units() * scale,
        masses=masses,
        volumes=volumes,
        elements=np.array(elements),
        kinds=np.array(kinds),
        stiffness=stiffness_scale * np.array([HOOP_STIFFNESS if _is_hoop(pair) else _STIFFNESS[k]
                                              for pair, k in zip(elements, kinds)]),
        damping=np.array([_DAMPING[k] for k in kinds]),
        actuator=np.array(actuator),
        actuator_names=ACTUATOR_NAMES,
        max_contraction=max_contraction,
        faces=faces,
        face_weights=weights,
        fin_nodes=np.array([[1, 4, 5, 8], [2, 3, 6, 7]]),
        fin_areas=np.array([fin_area, fin_area]),
        fin_names=("left", "right"),
        frame_front=np.array([0, 1, 2, 3, 4]),
        frame_back=np.array([9, 10, 11, 12]),
        frame_up=np.array([1, 2, 5, 6, 9, 10]),
        frame_down=np.array([3, 4, 7, 8, 11, 12]),
        length=length,
        **fish_sections(scale),
    )
