"""A body is data: the description of a mass-spring animal that the physics simulates.

A :class:`BodySpec` holds everything that is fixed about one animal's body (node masses, rest
shape, Voigt elements, muscles, hydrodynamic faces, fins, buoyancy); nothing here changes while
the animal moves. A new animal (the dolphin, later) is a new ``BodySpec``, not new physics.

Conventions (shared by every body):

* SI units: metres, kilograms, seconds, newtons.
* Body frame: x forward (the nose is the most forward node), y to the animal's left, z up.
  ``rest_positions`` are given in that frame.
* Element kinds: ``CROSS`` (diagonal struts, stiffest), ``ORDINARY`` (the surface edges) and
  ``MUSCLE`` (contractile; rest length ``l0 * (1 - max_contraction * u)`` for activation u).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

# the part of the body a face belongs to (BodySpec.face_parts): what a contact reports
BODY_PART, NOSE_PART, TAIL_PART = 0, 1, 2

CROSS, ORDINARY, MUSCLE = 0, 1, 2
KIND_NAMES = ("cross", "ordinary", "muscle")


def frozen_array(array: np.ndarray, dtype: type = np.float64) -> np.ndarray:
    """A contiguous read-only copy of ``array`` (fixed parameters must not change)."""
    out: np.ndarray = np.ascontiguousarray(array, dtype=dtype).copy()
    out.flags.writeable = False
    return out


@dataclass(frozen=True, eq=False)
class BodySpec:
    """Fixed description of a mass-spring body (N nodes, E elements, F faces, P fins, A actuators).

    Attributes:
        name: what the body is, e.g. ``"fish"``.
        rest_positions: (N, 3) rest shape in the body frame, m.
        masses: (N,) nodal masses, kg.
        volumes: (N,) displaced volume attributed to each node, m^3 (buoyancy acts there).
        elements: (E, 2) node index pairs of the Voigt elements.
        kinds: (E,) element kind (``CROSS``, ``ORDINARY``, ``MUSCLE``).
        stiffness: (E,) spring stiffness c, N/m.
        damping: (E,) damper coefficient gamma along the element, N s/m.
        actuator: (E,) actuator index driving each muscle element, -1 for passive elements.
        actuator_names: (A,) names in action order.
        max_contraction: fraction by which a fully activated muscle shortens its rest length.
        faces: (F, 4) node indices of hydrodynamic faces; a triangle repeats its last node.
        face_weights: (F, 4) share of each corner in the face (rows sum to 1, 0 for a repeat).
        fin_nodes: (P, K) nodes each pectoral fin is attached to (its force is shared equally).
        fin_areas: (P,) fin areas, m^2.
        fin_names: (P,) names, e.g. ``("left", "right")``.
        frame_front, frame_back: node lists whose centroids define the heading (back -> front).
        frame_up, frame_down: node lists whose centroids define the up direction (down -> up).
        length: body length (nose to tail tip), m.
        lung_volumes: (N,) air held at each node, m^3 at surface pressure (buoyancy that
            shrinks with depth, Boyle's law; default none).
        face_parts: (F,) the part of the body each face belongs to, for contacts: 0 body,
            1 nose, 2 tail (:data:`animat.envs.physics.ball.PART_NAMES`; default all body).
        section_nodes: (J, K) the cross-sections of the body from head to tail, as the nodes
            each is the weighted mean of (a ring, the nose, the tail's trailing edge), for the
            water's reactive force (:mod:`animat.envs.physics.reactive`); each node in at most
            one section. Default none (J = 0): the body feels the resistive forces only.
        section_weights: (J, K) each node's share of its section (rows sum to 1).
        section_lengths: (J,) the length of body each section stands for, m (they add up to
            the body's length).
        section_areas: (J,) the section's added mass per unit length per unit water density
            for motion across it in the body's plane of undulation, m^2: ``pi b^2`` for a
            half-extent b across the motion (an ellipse's, or a thin plate's of span 2b;
            Lighthill 1960). The force pushes each section across itself in that plane
            (:mod:`animat.envs.physics.reactive`).
        section_up, section_down: (J, K') for each section the nodes whose centroids give its
            axis across the plane of undulation (down -> up): the fish's up for every section
            (its lateral undulation; the default, ``frame_up`` and ``frame_down`` on every
            row), the dolphin's left for each of its rings and flukes their own (its vertical
            undulation: a section's normal stays defined however the tail bends).
    """

    name: str
    rest_positions: np.ndarray
    masses: np.ndarray
    volumes: np.ndarray
    elements: np.ndarray
    kinds: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    actuator: np.ndarray
    actuator_names: tuple[str, ...]
    max_contraction: float
    faces: np.ndarray
    face_weights: np.ndarray
    fin_nodes: np.ndarray
    fin_areas: np.ndarray
    fin_names: tuple[str, ...]
    frame_front: np.ndarray
    frame_back: np.ndarray
    frame_up: np.ndarray
    frame_down: np.ndarray
    length: float = field(default=0.0)
    # None: zeros (no air; every face part of the body), filled in by __post_init__
    lung_volumes: np.ndarray = None  # type: ignore[assignment]
    face_parts: np.ndarray = None  # type: ignore[assignment]
    section_nodes: np.ndarray = None  # type: ignore[assignment]
    section_weights: np.ndarray = None  # type: ignore[assignment]
    section_lengths: np.ndarray = None  # type: ignore[assignment]
    section_areas: np.ndarray = None  # type: ignore[assignment]
    section_up: np.ndarray = None  # type: ignore[assignment]
    section_down: np.ndarray = None  # type: ignore[assignment]

    def __post_init__(self) -> None:
        if self.section_nodes is None:
            for name, shape in (("section_nodes", (0, 1)), ("section_weights", (0, 1)),
                                ("section_lengths", (0,)), ("section_areas", (0,))):
                object.__setattr__(self, name, np.zeros(shape))
        if (self.section_up is None) != (self.section_down is None):
            raise ValueError(f"BodySpec {self.name!r}: give both section_up and section_down, "
                             "or neither (the front's up on every section)")
        if self.section_up is None:
            rows = len(self.section_nodes)
            object.__setattr__(self, "section_up", np.tile(self.frame_up, (rows, 1)))
            object.__setattr__(self, "section_down", np.tile(self.frame_down, (rows, 1)))
        if self.lung_volumes is None:
            object.__setattr__(self, "lung_volumes", np.zeros(len(self.masses)))
        if self.face_parts is None:
            object.__setattr__(self, "face_parts", np.zeros(len(self.faces)))
        conversions = {
            "rest_positions": float, "masses": float, "volumes": float, "elements": np.int64,
            "kinds": np.int64, "stiffness": float, "damping": float, "actuator": np.int64,
            "faces": np.int64, "face_weights": float, "fin_nodes": np.int64, "fin_areas": float,
            "frame_front": np.int64, "frame_back": np.int64, "frame_up": np.int64,
            "frame_down": np.int64, "lung_volumes": float, "face_parts": np.int64,
            "section_nodes": np.int64, "section_weights": float, "section_lengths": float,
            "section_areas": float, "section_up": np.int64, "section_down": np.int64,
        }
        for name, dtype in conversions.items():
            object.__setattr__(self, name, frozen_array(getattr(self, name), dtype))
        if self.length <= 0.0:
            extent = self.rest_positions[:, 0].max() - self.rest_positions[:, 0].min()
            object.__setattr__(self, "length", float(extent))
        validate_body(self)

    @property
    def num_nodes(self) -> int:
        return int(self.rest_positions.shape[0])

    @property
    def num_elements(self) -> int:
        return int(self.elements.shape[0])

    @property
    def num_muscles(self) -> int:
        return int(np.count_nonzero(self.kinds == MUSCLE))

    @property
    def num_actuators(self) -> int:
        return len(self.actuator_names)

    @property
    def num_fins(self) -> int:
        return int(self.fin_nodes.shape[0])

    def action_size(self, fins: bool) -> int:
        """An env step's action length: one activation per actuator, and with ``fins`` one
        angle per pectoral fin after them."""
        return self.num_actuators + (self.num_fins if fins else 0)

    @property
    def total_mass(self) -> float:
        return float(self.masses.sum())

    @property
    def rest_lengths(self) -> np.ndarray:
        """(E,) element rest lengths in the rest shape, m."""
        i, j = self.elements[:, 0], self.elements[:, 1]
        return np.linalg.norm(self.rest_positions[j] - self.rest_positions[i], axis=1)


def validate_body(body: BodySpec) -> None:
    """Raise ValueError naming the first inconsistency in a body description."""
    n, e = body.rest_positions.shape[0], body.elements.shape[0]
    checks = [
        (body.rest_positions.shape == (n, 3), "rest_positions must have shape (N, 3)"),
        (body.masses.shape == (n,) and np.all(body.masses > 0), "masses must be (N,) and > 0"),
        (body.volumes.shape == (n,) and np.all(body.volumes >= 0), "volumes must be (N,) >= 0"),
        (body.lung_volumes.shape == (n,) and np.all(body.lung_volumes >= 0),
         "lung_volumes must be (N,) >= 0"),
        (body.elements.shape == (e, 2), "elements must have shape (E, 2)"),
        (body.elements.min() >= 0 and body.elements.max() < n, "elements index a missing node"),
        (np.all(body.elements[:, 0] != body.elements[:, 1]), "an element joins a node to itself"),
        (body.kinds.shape == (e,) and set(np.unique(body.kinds)) <= {CROSS, ORDINARY, MUSCLE},
         "kinds must be (E,) of CROSS/ORDINARY/MUSCLE"),
        (body.stiffness.shape == (e,) and np.all(body.stiffness > 0), "stiffness must be > 0"),
        (body.damping.shape == (e,) and np.all(body.damping >= 0), "damping must be >= 0"),
        (np.array_equal(body.actuator >= 0, body.kinds == MUSCLE),
         "exactly the muscle elements must have an actuator"),
        (body.actuator.max() < len(body.actuator_names), "an actuator index has no name"),
        (0.0 < body.max_contraction < 1.0, "max_contraction must be in (0, 1)"),
        (body.faces.ndim == 2 and body.faces.shape[1] == 4, "faces must have shape (F, 4)"),
        (body.face_weights.shape == body.faces.shape, "face_weights must match faces"),
        (body.face_parts.shape == (body.faces.shape[0],) and set(np.unique(body.face_parts))
         <= {0, 1, 2}, "face_parts must be (F,) of 0 (body), 1 (nose), 2 (tail)"),
        (np.allclose(body.face_weights.sum(axis=1), 1.0), "face_weights rows must sum to 1"),
        (body.fin_areas.shape == (body.fin_nodes.shape[0],), "one fin area per fin"),
        (len(body.fin_names) == body.fin_nodes.shape[0], "one fin name per fin"),
    ]
    for ok, message in checks + section_checks(body):
        if not ok:
            raise ValueError(f"BodySpec {body.name!r}: {message}")
    lengths = body.rest_lengths
    if np.any(lengths <= 0):
        raise ValueError(f"BodySpec {body.name!r}: an element has zero rest length")


def section_checks(body: BodySpec) -> list[tuple[bool, str]]:
    """(ok, message) pairs for the cross-sections (:attr:`BodySpec.section_nodes`)."""
    nodes, weights = body.section_nodes, body.section_weights
    j = nodes.shape[0]
    used = nodes[weights > 0] if weights.shape == nodes.shape else nodes.ravel()
    return [
        (nodes.ndim == 2 and weights.shape == nodes.shape, "section_weights must match "
         "section_nodes (J, K)"),
        (j == 0 or (nodes.min() >= 0 and nodes.max() < body.num_nodes),
         "section_nodes index a missing node"),
        (j == 0 or (np.all(weights >= 0) and np.allclose(weights.sum(axis=1), 1.0)),
         "section_weights must be >= 0 with rows summing to 1"),
        (len(np.unique(used)) == len(used), "a node is in more than one section"),
        (body.section_lengths.shape == (j,) and np.all(body.section_lengths >= 0),
         "section_lengths must be (J,) >= 0"),
        (body.section_areas.shape == (j,) and np.all(body.section_areas >= 0),
         "section_areas must be (J,) >= 0"),
        (j != 1, "a body needs no section or at least two (head and tail)"),
        (all(g.ndim == 2 and g.shape[0] == j and (j == 0 or (g.shape[1] > 0 and g.min() >= 0
             and g.max() < body.num_nodes)) for g in (body.section_up, body.section_down)),
         f"section_up and section_down must be (J, K') of the body's nodes, a row a section "
         f"(J = {j}), got shapes {body.section_up.shape} and {body.section_down.shape}"),
    ]


def chain_sections(stations: list[float], groups: list[list[int]],
                   half_extents: list[float], scale: float) -> dict[str, np.ndarray]:
    """The cross-section fields of a :class:`BodySpec` for a body laid out as a chain of
    stations, head to tail: station k at body-frame x ``stations[k]`` (model units, falling
    toward the tail) holds the nodes ``groups[k]`` (equal shares) and has the half-extent
    ``b = half_extents[k]`` (model units) across the plane of undulation: its added-mass area
    is ``pi b^2``. Each section stands for the
    body from half-way to the station in front to half-way to the one behind (the first from
    its own x, the last to its own x). ``scale`` is metres per model unit."""
    xs = np.asarray(stations, dtype=float)
    bounds = np.concatenate([[xs[0]], 0.5 * (xs[1:] + xs[:-1]), [xs[-1]]])
    width = max(len(g) for g in groups)

    nodes = np.array([g + [g[-1]] * (width - len(g)) for g in groups])
    weights = np.array([[1.0 / len(g)] * len(g) + [0.0] * (width - len(g)) for g in groups])
    areas = np.pi * np.asarray(half_extents, dtype=float) ** 2
    return {"section_nodes": nodes, "section_weights": weights,
            "section_lengths": (bounds[:-1] - bounds[1:]) * scale,
            "section_areas": areas * scale**2}
