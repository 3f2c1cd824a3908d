"""Fixed physical parameters of a simulation: the frozen :class:`Water` and :class:`System`.

Following Brax's split, everything that does not change during a rollout (the body, the
water, the integration step, the constants derived from them) lives in a frozen
:class:`System`; the moving parts (node positions and velocities) are the batched arrays the
env core keeps. ``System.kernel_args`` hands the constants to the compiled step kernel
(:mod:`animat.envs.physics.integrator`) as one named tuple; its ``water`` is the one float
array :meth:`Water.as_args` packs, which the kernels read by the slot constants defined here
(``water[SURFACE_Z]``, :data:`WATER_SLOTS`), never by a bare number.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from dataclasses import fields as dataclass_fields
from functools import cached_property
from typing import NamedTuple

import numpy as np

from ..bodies.spec import BodySpec, frozen_array
from ..checks import check_number, check_vector, is_real, shown

REACTION_LAWS = ("crossflow", "paper")
WATER_MODELS = ("reactive", "resistive")
MAX_ADDED_MASS = 4.0  # the largest added-mass coefficient (1 is Lighthill's section)
# The ranges Water accepts (low, high, unit; air_pressure must be above its low): physically
# sensible media that the integrator keeps finite, every field at its bound at once, at the
# largest physics_dt System accepts, with the reset noise at its bound (tests/envs/
# test_env_arguments.py). Drag kappa = 0.5 rho C_d of a liquid no denser than 2e4 kg/m^3
# (mercury: 13,534) with C_d up to 2; skin friction 0.5 rho C_f with C_f up to 0.1 in water
# (laminar flow at Re ~ 200; the fish's steps turn unstable at about 200, four times more);
# up to 10 g; up to 100 bar at the surface.
MAX_KAPPA, MAX_FRICTION = 2e4, 50.0  # kg/m^3, the drag and the skin friction coefficients'
WATER_LIMITS = {"fluid_coefficient": (0.0, MAX_KAPPA, "kg/m^3"),
                "air_coefficient": (0.0, MAX_KAPPA, "kg/m^3"),
                "friction_coefficient": (0.0, MAX_FRICTION, "kg/m^3"),
                "air_friction_coefficient": (0.0, MAX_FRICTION, "kg/m^3"),
                "density": (0.0, 2e4, "kg/m^3"), "gravity": (0.0, 100.0, "m/s^2"),
                "air_pressure": (0.0, 1e7, "Pa")}
# The reactive water's added mass per volume, density x added_mass, and its density: at most
# 1100 kg/m^3 (sea water, 1025), where the default step stays stable. Above it the caudal fin
# whips under random actions: the added mass sits on the tail's light nodes, and the explicit
# step then needs a smaller step to hold it.
MAX_REACTIVE_DENSITY = 1100.0  # kg/m^3
MAX_CURRENT = 20.0  # m/s, each component of the current (the fastest rivers: ~7 m/s)
MAX_SURFACE_Z = 1e4  # m, the largest |surface_z| but inf (no surface)


@dataclass(frozen=True)
class Water:
    """The medium the body moves in.

    Attributes:
        fluid_coefficient: kappa of the face reaction force, kg/m^3 (``0.5 rho C_d``; a flat
            plate's C_d of 1 in water gives 500).
        air_coefficient: the same above the surface (0.5 * 1.2 kg/m^3 * 1).
        friction_coefficient: kappa_f of the skin friction along each face, kg/m^3
            (``0.5 rho C_f``; C_f = 0.006, turbulent flat plate at Re ~ 1e5, gives 3).
        air_friction_coefficient: the same above the surface.
        reaction: ``"crossflow"`` (normal force ``kappa A (n.w)^2``) or ``"paper"`` (the data
            sheet's ``kappa A (n.w) |w|``); see :mod:`animat.envs.physics.forces`.
        density: water density for buoyancy, kg/m^3.
        gravity: m/s^2, acting along -z.
        surface_z: height of the water surface, m (``inf``: no surface, everything submerged).
        current: (3,) water velocity in the world frame, m/s.
        air_pressure: at the surface, Pa; sets how lungs compress with depth (Boyle's law,
            :func:`animat.envs.physics.forces.compressed`).
        model: ``"reactive"`` (the default) adds to the resistive forces the water's reactive
            force of Lighthill's elongated-body theory on the body's cross-sections (added mass
            and the momentum shed at the trailing edge; :mod:`animat.envs.physics.reactive`); it
            needs a body with cross-sections (``BodySpec.section_nodes``: the fish and the
            dolphin have them). ``"resistive"`` is the paper's water of 1995, the faces' drag and
            friction alone.
        added_mass: the reactive model's added mass as a multiple of the sections'
            (``rho pi b^2`` per unit length), dimensionless, in [0, 4].

    ``Water(fluid_coefficient=0, air_coefficient=0, friction_coefficient=0, gravity=0, density=0)``
    is a vacuum (:func:`vacuum`). Each field must be finite and within its range: the two drag
    coefficients and ``density`` in [0, 2e4] kg/m^3 (in the reactive water ``density`` and
    ``density * added_mass`` at most 1100, :data:`MAX_REACTIVE_DENSITY`), the two friction
    coefficients in [0, 50] kg/m^3, ``gravity`` in [0, 100] m/s^2, ``added_mass`` in [0, 4],
    ``air_pressure`` in (0, 1e7] Pa (:data:`WATER_LIMITS`), each ``current`` component in [-20, 20]
    m/s, ``surface_z`` in [-1e4, 1e4] m or ``inf``; a bad one is a ValueError of one line naming
    the field and its value.
    """

    fluid_coefficient: float = 500.0
    air_coefficient: float = 0.6
    friction_coefficient: float = 3.0
    air_friction_coefficient: float = 0.0036
    reaction: str = "crossflow"
    density: float = 1000.0
    gravity: float = 9.81
    surface_z: float = float("inf")
    current: tuple[float, float, float] = (0.0, 0.0, 0.0)
    air_pressure: float = 101325.0
    model: str = "reactive"
    added_mass: float = 1.0

    def __post_init__(self) -> None:
        """Check every field: a finite number in its range (:data:`WATER_LIMITS`), ``current``
        within +-``MAX_CURRENT`` m/s, ``surface_z`` also ``inf`` (no surface); a bad one is a
        ValueError of one line naming the field and its value."""
        for name, (low, high, unit) in WATER_LIMITS.items():
            check_number(f"Water.{name}", getattr(self, name), low, high, unit,
                         low_open=name == "air_pressure")
        if not (isinstance(self.reaction, str) and self.reaction in REACTION_LAWS):
            raise ValueError(f"Water.reaction must be one of {REACTION_LAWS}, got "
                             f"{shown(self.reaction)}")
        if not (isinstance(self.model, str) and self.model in WATER_MODELS):
            raise ValueError(f"Water.model must be one of {WATER_MODELS}, got "
                             f"{shown(self.model)}")
        check_number("Water.added_mass", self.added_mass, 0.0, MAX_ADDED_MASS, "")
        if self.model == "reactive":
            check_number("Water.density", self.density, 0.0, MAX_REACTIVE_DENSITY, "kg/m^3",
                         note="in the reactive water; the resistive one takes up to 2e4")
            check_number("Water.density x added_mass", self.density * self.added_mass, 0.0,
                         MAX_REACTIVE_DENSITY, "kg/m^3", note="in the reactive water")
        if not (is_real(self.surface_z) and self.surface_z == float("inf")):
            check_number("Water.surface_z", self.surface_z, -MAX_SURFACE_Z, MAX_SURFACE_Z, "m",
                         note="or inf: no surface")
        current = check_vector("Water.current", self.current, 3, -MAX_CURRENT, MAX_CURRENT,
                               "m/s")
        object.__setattr__(self, "current", current)

    @classmethod
    def from_dict(cls, fields: dict | Water | None) -> Water:
        """A Water from a dict of its fields (unknown names are an error naming them)."""
        if fields is None:
            return cls()
        if isinstance(fields, Water):
            return fields
        if not isinstance(fields, dict):
            raise ValueError(f"water must be a dict of Water fields, got {shown(fields)}")
        unknown = sorted(set(fields) - set(asdict(cls())))
        if unknown:
            raise ValueError(f"water: unknown field(s) {unknown}; known: "
                             f"{sorted(asdict(cls()))}")
        return cls(**fields)

    def as_args(self) -> np.ndarray:
        """(WATER_SIZE,) float64, the numbers the compiled force terms read: the one place the
        water is packed for the kernels. A slot per number, the fields in their order (SI
        units as above), ``reaction`` as the flag ``crossflow`` (1.0 cross-flow, 0.0 paper),
        ``model`` as the flag ``reactive`` (1.0 reactive, 0.0 resistive)
        and ``current`` as its x, y, z components (:data:`SPLIT_FIELDS`); a kernel reads slot
        ``water[SURFACE_Z]`` by its constant (:data:`WATER_SLOTS`)."""
        numbers = {"reaction": (1.0 if self.reaction == "crossflow" else 0.0,),
                   "current": self.current,
                   "model": (1.0 if self.model == "reactive" else 0.0,)}
        return np.array([number for f in dataclass_fields(self)
                         for number in numbers.get(f.name, (getattr(self, f.name),))],
                        dtype=np.float64)


# The water as the kernels see it (Water.as_args): one float64 array, a slot per number, Water's
# fields in their order, each one slot but these, named here by their slots.
SPLIT_FIELDS = {"reaction": ("crossflow",), "current": ("current_x", "current_y", "current_z"),
                "model": ("reactive",)}
WATER_SLOTS: tuple[str, ...] = tuple(slot for f in dataclass_fields(Water)
                                     for slot in SPLIT_FIELDS.get(f.name, (f.name,)))
WATER_SIZE = len(WATER_SLOTS)
_SLOT = {name: index for index, name in enumerate(WATER_SLOTS)}
# Each slot's index, from the order above (the names are WATER_SLOTS' in capitals; tests/envs/
# physics/test_water.py checks both agree and round-trip, and pins the order). Module-level
# ints, so a Numba kernel reading ``water[SURFACE_Z]`` compiles it as a constant index, as
# fast as a literal; Numba's on-disk cache does not see a change made here, so clear
# envs/**/__pycache__ after reordering Water.
FLUID_COEFFICIENT: int = _SLOT["fluid_coefficient"]  # kg/m^3, drag kappa under the surface
AIR_COEFFICIENT: int = _SLOT["air_coefficient"]  # kg/m^3, drag kappa above it
FRICTION_COEFFICIENT: int = _SLOT["friction_coefficient"]  # kg/m^3, skin friction, under
AIR_FRICTION_COEFFICIENT: int = _SLOT["air_friction_coefficient"]  # kg/m^3, above
CROSSFLOW: int = _SLOT["crossflow"]  # 1.0 the cross-flow reaction law, 0.0 the paper's
DENSITY: int = _SLOT["density"]  # kg/m^3, for buoyancy and the splash
GRAVITY: int = _SLOT["gravity"]  # m/s^2, along -z
SURFACE_Z: int = _SLOT["surface_z"]  # m, the surface's height (inf: none)
CURRENT_X: int = _SLOT["current_x"]  # m/s, the water's velocity in the world frame
CURRENT_Y: int = _SLOT["current_y"]  # m/s
CURRENT_Z: int = _SLOT["current_z"]  # m/s
AIR_PRESSURE: int = _SLOT["air_pressure"]  # Pa, at the surface (lungs' compression)
REACTIVE: int = _SLOT["reactive"]  # 1.0 the reactive (added-mass) water, 0.0 resistive only
ADDED_MASS: int = _SLOT["added_mass"]  # the reactive force's added-mass coefficient


def vacuum() -> Water:
    """No fluid, no friction, no gravity: internal forces only (``density`` 0: no added mass
    either)."""
    return Water(fluid_coefficient=0.0, air_coefficient=0.0, friction_coefficient=0.0,
                 air_friction_coefficient=0.0, gravity=0.0, density=0.0)


class KernelArgs(NamedTuple):
    """What the compiled step reads (see :class:`~envs.bodies.spec.BodySpec` for the body's
    arrays)."""

    masses: np.ndarray
    volumes: np.ndarray
    lungs: np.ndarray
    elements: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    rest_lengths: np.ndarray
    actuator: np.ndarray
    max_contraction: float
    faces: np.ndarray
    face_weights: np.ndarray
    face_mass: np.ndarray
    fin_nodes: np.ndarray
    fin_areas: np.ndarray
    fin_mass: np.ndarray
    frame_front: np.ndarray
    frame_back: np.ndarray
    frame_up: np.ndarray
    frame_down: np.ndarray
    water: np.ndarray  # (WATER_SIZE,) Water.as_args, read as water[SURFACE_Z] etc.
    dt: float
    section_nodes: np.ndarray
    section_weights: np.ndarray
    section_lengths: np.ndarray
    section_areas: np.ndarray
    section_up: np.ndarray
    section_down: np.ndarray
    implicit_band: int  # 0: symplectic Euler; W > 0: the implicit step, its half-bandwidth W
    theta: float  # the implicit step's theta (1: backward Euler)


DEFAULT_DT = 0.05 / 40  # s; 40 steps per 0.05 s env step (docs/physics.md: the convergence table)
INTEGRATORS = ("explicit", "implicit")
MAX_IMPLICIT_DT = 0.1  # s, the largest step of the implicit integrator (two default env steps)
STABILITY_MARGIN = 0.75  # the largest dt System accepts, as a share of stable_step
# (why 0.75: stable_step is the linear bound at rest. Undamped, from a 2 mm random perturbation,
# steps at 85% of it let the energy creep up and blow up after ~370 s (large stretches stiffen
# the body); at 74% it stayed within +-15% over 480 s on every seed tried.)


@dataclass(frozen=True, eq=False)
class System:
    """A body in water, integrated with a fixed step ``dt`` (s) by ``integrator``.

    ``integrator`` (as MuJoCo's option of that name): ``"explicit"``, symplectic Euler
    (:mod:`animat.envs.physics.integrator`; ``dt`` must lie within ``STABILITY_MARGIN`` of
    the body's explicit stability bound, :func:`stable_step`, a larger one is refused with the
    limit in the message), or ``"implicit"``, the linearised theta-method with the elements'
    stiffness and damping, the faces' drag and the water's added mass on the left side
    (:mod:`animat.envs.physics.implicit`; ``dt`` up to ``MAX_IMPLICIT_DT``; ``theta`` in
    [0.5, 1], 1 backward Euler).

    Derived constants (computed once):
        face_mass: (F,) mass a face's own force meets, ``1 / sum_k w_k^2 / m_k``, kg.
        fin_mass: (P,) the same for each fin, kg.
    """

    body: BodySpec
    water: Water = field(default_factory=Water)
    dt: float = DEFAULT_DT
    integrator: str = "explicit"
    theta: float = 1.0
    face_mass: np.ndarray = field(init=False, repr=False)
    fin_mass: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if not (np.isfinite(self.dt) and self.dt > 0):
            raise ValueError(f"System.dt must be a positive number of seconds, got {self.dt!r}")
        if not (isinstance(self.integrator, str) and self.integrator in INTEGRATORS):
            raise ValueError(f"System.integrator must be one of {INTEGRATORS}, got "
                             f"{shown(self.integrator)}")
        implicit = self.integrator == "implicit"
        check_number("System.theta", self.theta, 0.5, 1.0, "")
        limit = MAX_IMPLICIT_DT if implicit else STABILITY_MARGIN * stable_step(self.body)
        if implicit and self.dt > limit:
            raise ValueError(f"System.dt = {self.dt:g} s is above the implicit integrator's "
                             f"largest step ({limit:g} s); use a smaller physics_dt")
        if self.dt > limit:
            raise ValueError(f"System.dt = {self.dt:g} s is above the stability bound of body "
                             f"{self.body.name!r} for this integrator ({limit:.3g} s); use a "
                             "smaller physics_dt")
        if self.water.model == "reactive" and self.body.section_nodes.shape[0] == 0:
            raise ValueError(f"the reactive water needs a body with cross-sections; body "
                             f"{self.body.name!r} has none: use water={{'model': 'resistive'}}")
        fin_weights = np.full(self.body.fin_nodes.shape, 1.0 / self.body.fin_nodes.shape[1])
        object.__setattr__(self, "face_mass", frozen_array(effective_masses(
            self.body.masses, self.body.faces, self.body.face_weights)))
        object.__setattr__(self, "fin_mass", frozen_array(effective_masses(
            self.body.masses, self.body.fin_nodes, fin_weights)))

    @cached_property
    def kernel_args(self) -> KernelArgs:
        """Constants for :func:`animat.envs.physics.integrator.step_batch`."""
        b = self.body
        return KernelArgs(
            b.masses, b.volumes, b.lung_volumes, b.elements, b.stiffness, b.damping,
            b.rest_lengths, b.actuator, float(b.max_contraction), b.faces, b.face_weights,
            self.face_mass, b.fin_nodes, b.fin_areas, self.fin_mass, b.frame_front,
            b.frame_back, b.frame_up, b.frame_down,
            frozen_array(self.water.as_args()), float(self.dt), b.section_nodes,
            b.section_weights, b.section_lengths, b.section_areas, b.section_up, b.section_down,
            half_bandwidth(b.elements, b.faces) if self.integrator == "implicit" else 0,
            float(self.theta))


def half_bandwidth(elements: np.ndarray, faces: np.ndarray) -> int:
    """The implicit step's banded matrix's half-bandwidth in unknowns, ``3 max|i - j| + 2``
    over the nodes i, j of each of the ``elements`` (E, 2) and of each of the ``faces`` (F, 4)
    (:mod:`animat.envs.physics.implicit`)."""
    span = max(np.ptp(elements, axis=1).max(), np.ptp(faces, axis=1).max() if len(faces) else 0)
    return int(3 * span + 2)


def effective_masses(masses: np.ndarray, nodes: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """(F,) the mass a force spread over ``nodes`` (F, K) with ``weights`` (F, K) meets: its
    weighted mean velocity changes by ``F dt sum_k w_k^2 / m_k``, kg."""
    compliance = np.zeros(nodes.shape[0])
    for k in range(nodes.shape[1]):
        compliance += weights[:, k] ** 2 / masses[nodes[:, k]]
    return 1.0 / compliance


def element_matrix(body: BodySpec, coefficients: np.ndarray) -> np.ndarray:
    """(3N, 3N) stiffness-like matrix ``sum_e k_e (d_e d_e')`` of the elements at rest, with
    ``coefficients`` (E,) per element (the stiffness gives K, the damping D)."""
    n, x = body.num_nodes, body.rest_positions
    matrix = np.zeros((3 * n, 3 * n))
    for (i, j), k in zip(body.elements, coefficients):
        d = x[j] - x[i]
        block = k * np.outer(d, d) / (d @ d)
        for a, b, sign in ((i, i, 1.0), (j, j, 1.0), (i, j, -1.0), (j, i, -1.0)):
            matrix[3 * a:3 * a + 3, 3 * b:3 * b + 3] += sign * block
    return matrix


def stable_step(body: BodySpec) -> float:
    """Largest step (s) at which symplectic Euler is stable for the body at rest: the h with
    ``h^2 omega^2 + 2 h c = 4`` for the stiffest mode omega^2 (of M^-1 K) and the fastest
    damping rate c (of M^-1 D), from the damped oscillator's amplification matrix. Muscle
    contraction and large stretches move it, hence the margin in :class:`System`."""
    inverse_mass = np.repeat(1.0 / body.masses, 3)
    scale = np.sqrt(inverse_mass)
    omega2 = np.linalg.eigvalsh(scale[:, None] * element_matrix(body, body.stiffness)
                                * scale[None, :]).max()
    rate = np.linalg.eigvalsh(scale[:, None] * element_matrix(body, body.damping)
                              * scale[None, :]).max()
    return float((-rate + np.sqrt(rate * rate + 4.0 * omega2)) / omega2)
