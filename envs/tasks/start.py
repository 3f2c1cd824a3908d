"""Where an episode starts: :class:`StartSpread`, the documented distribution of start states
that every task draws from (its ``start_spread``; an env's ``start_spread`` argument changes
it), and :func:`spread_start`, which moves a task's placed body to one draw of it.

A start is the task's placement (:meth:`animat.envs.tasks.base.Task.place` and
``start_velocity``) moved, in this order, by

1. a **bend**: the body curved sideways into an arc about its own axis (its heading kept), the
   angle between its nose and tail tangents uniform in ``+-bend_deg``;
2. a **pitch** about its own lateral axis through the centre of mass, uniform in
   ``+-pitch_deg`` (nose up positive);
3. a **heading**: a yaw about the vertical through the centre of mass, uniform in
   ``+-heading_deg``; the tasks measure from it (``World.start_yaw``), so a swim, a turn or a
   reach goal is the same task whichever way the body starts;
4. a **position**: the centre of mass moved horizontally by up to ``+-position_bl`` and
   vertically by up to ``+-depth_bl`` body lengths (each uniform);
5. a **velocity**: a glide forward uniform in ``[0, speed_bl]`` BL/s, a drift sideways in
   ``+-drift_bl`` BL/s and a yaw rate in ``+-yaw_rate_deg`` deg/s (a rigid rotation about the
   centre of mass), added to the task's start velocity (which turns with the body).

Then the env's ``reset_noise_scale`` moves each node coordinate. In still, boundless water the
heading and the position change nothing but rounding (the physics is rotation and translation
invariant, tested); the bend and the velocity change what the body does. :data:`POINT_START`
is the start every env had before the spread existed (the placement alone): a start spread of
``"point"``.

Ranges (each a ValueError of one line naming it): ``heading_deg`` in [0, 180], ``pitch_deg`` and
``bend_deg`` in [0, 45], ``speed_bl`` in [0, 3] BL/s, ``drift_bl`` in [0, 1] BL/s,
``yaw_rate_deg`` in [0, 180] deg/s, ``position_bl`` in [0, 100] BL, ``depth_bl`` in [0, 10]
BL: a bent body's springs stay within their working strain, and a start glide below a cruise.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields, replace

import numpy as np

from ..checks import check_number, shown
from ..physics.observe import body_state

RANGES = {"heading_deg": (180.0, "deg"), "pitch_deg": (45.0, "deg"), "bend_deg": (45.0, "deg"),
          "speed_bl": (3.0, "BL/s"), "drift_bl": (1.0, "BL/s"),
          "yaw_rate_deg": (180.0, "deg/s"), "position_bl": (100.0, "BL"),
          "depth_bl": (10.0, "BL")}
DRAWS = 9  # uniform numbers a spread start draws (none for the point start)


@dataclass(frozen=True, slots=True, kw_only=True)
class StartSpread:
    """The spread of an episode's start about the task's placement (the module docstring):
    each field the half-width of a uniform draw (``speed_bl``: its upper end, from 0); all
    zero is the placement itself (:data:`POINT_START`)."""

    heading_deg: float = 0.0
    pitch_deg: float = 0.0
    bend_deg: float = 0.0
    speed_bl: float = 0.0
    drift_bl: float = 0.0
    yaw_rate_deg: float = 0.0
    position_bl: float = 0.0
    depth_bl: float = 0.0

    def __post_init__(self) -> None:
        for name, (high, unit) in RANGES.items():
            object.__setattr__(self, name, check_number(f"start_spread {name}",
                                                        getattr(self, name), 0.0, high, unit))

    @property
    def is_point(self) -> bool:
        """Whether every field is 0: the placement alone, drawing no random numbers."""
        return not any(getattr(self, field.name) for field in fields(self))

    def as_dict(self) -> dict[str, float]:
        """The fields by name (what a run folder records)."""
        return asdict(self)

    def over(self, value: StartSpread | dict | str | None) -> StartSpread:
        """``value`` as a spread with this one as its default: None this one, ``"point"``
        :data:`POINT_START`, a dict its fields over this one's, a StartSpread itself; else a
        ValueError of one line."""
        if value is None:
            return self
        if isinstance(value, StartSpread):
            return value
        if value == "point":
            return POINT_START
        if not isinstance(value, dict):
            raise ValueError(f"start_spread must be None, 'point' or a dict of "
                             f"{sorted(RANGES)}, got {shown(value)}")
        unknown = sorted(map(str, set(value) - {f.name for f in fields(StartSpread)}))
        if unknown:
            raise ValueError(f"start_spread has no field(s) {unknown}; its fields: "
                             f"{sorted(RANGES)}")
        return replace(self, **value)


POINT_START = StartSpread()
# The fish's tasks in open water: any heading, a body bent up to 20 deg, gliding at up to
# half a body length a second (its cruise is ~2.7 BL/s), drifting and yawing a little.
FISH_START = StartSpread(heading_deg=180.0, bend_deg=20.0, speed_bl=0.5, drift_bl=0.2,
                         yaw_rate_deg=30.0, position_bl=1.0)


def spread_start(placed: np.ndarray, velocity: np.ndarray, body, spread: StartSpread,
                 rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, float]:
    """One start of ``spread`` about the task's placed body: node positions ``placed`` (N, 3)
    m and velocities ``velocity`` (N, 3) m/s of ``body`` (a ``BodySpec``), the numbers drawn
    from ``rng`` (:data:`DRAWS` of them; none for the point start). Returns the nodes' positions
    and velocities and the start heading's yaw, rad, relative to the placement's."""
    if spread.is_point:
        return placed, velocity, 0.0
    u = rng.uniform(-1.0, 1.0, DRAWS)
    centre, frame = _centre_and_frame(placed, body)  # frame: rows forward, left, up
    local = bent((placed - centre) @ frame.T, body, np.radians(spread.bend_deg) * u[0])
    pitch, yaw = np.radians(spread.pitch_deg) * u[1], np.radians(spread.heading_deg) * u[2]
    to_world = yaw_matrix(yaw) @ frame.T @ pitch_matrix(pitch)
    arm = local @ to_world.T
    offset = body.length * np.array([spread.position_bl * u[3], spread.position_bl * u[4],
                                     spread.depth_bl * u[5]])
    forward, left = to_world[:, 0], to_world[:, 1]
    glide = body.length * (spread.speed_bl * 0.5 * (u[6] + 1.0) * forward
                           + spread.drift_bl * u[7] * left)
    yaw_rate = np.radians(spread.yaw_rate_deg) * u[8]
    rigid = yaw_rate * np.stack([-arm[:, 1], arm[:, 0], np.zeros(len(arm))], axis=1)
    turned = velocity @ (to_world @ frame).T  # the task's velocity turns with the body
    return centre + offset + arm, turned + glide + rigid, float(yaw)


def bent(local: np.ndarray, body, angle: float) -> np.ndarray:
    """(N, 3) the body's nodes ``local`` (in its own frame about its centre of mass: forward,
    left, up) curved sideways into an arc whose end tangents differ by ``angle`` rad (positive:
    both ends to the left), each node kept at its distance from the axis; then moved back so
    that its centre of mass and its heading (the frame of ``body.frame_front``/``frame_back``)
    are the unbent body's."""
    if angle == 0.0:
        return local
    kappa = angle / body.length
    s, w = local[:, 0], local[:, 1]
    arc = np.stack([np.sin(kappa * s) / kappa - w * np.sin(kappa * s),
                    (1.0 - np.cos(kappa * s)) / kappa + w * np.cos(kappa * s),
                    local[:, 2]], axis=1)
    centre, frame = _centre_and_frame(arc, body)
    heading = np.arctan2(frame[0, 1], frame[0, 0])
    return (arc - centre) @ yaw_matrix(-heading).T


def _centre_and_frame(x: np.ndarray, body) -> tuple[np.ndarray, np.ndarray]:
    """The centre of mass (3,) and the body frame (3, 3) (rows forward, left, up) of nodes
    ``x`` (N, 3) of ``body``."""
    com, _, frames = body_state(x[None], np.zeros_like(x)[None], body.masses,
                                body.frame_front, body.frame_back, body.frame_up,
                                body.frame_down)
    return com[0], frames[0]


def yaw_matrix(angle: float) -> np.ndarray:
    """(3, 3) the rotation by ``angle`` rad about +z (to the left)."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def pitch_matrix(angle: float) -> np.ndarray:
    """(3, 3) the rotation by ``angle`` rad nose up about the body's left axis (+y of its own
    frame): forward (1, 0, 0) goes to (cos, 0, sin)."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]])
