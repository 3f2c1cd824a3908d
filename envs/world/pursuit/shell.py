"""What the pursuit's single env and its native vector env share around their batched core
(:class:`~animat.envs.world.pursuit.worlds.PursuitWorlds`): the arguments' checks
(:func:`pursuit_params`), the observation's sensors and space (:func:`pursuit_observer`),
the worlds' ``info`` (:func:`world_infos`) and the pictures (:func:`render_world`).
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np

from ...bodies.fish import fish_body
from ...checks import check_flag, check_integer, check_number, check_range, shown
from ...core.batch import Kinematics
from ...render.camera import Camera, look_at
from ...vision.perception import triangulate
from ...vision.retina import Retina, RetinaParams, composite
from .senses import ObserverView, PreyPosition, PursuitObserver, default_sensors
from .start import DISTRACTOR, PREY
from .worlds import PursuitParams, PursuitWorlds

DEFAULT_DURATION = 20.0  # s, a pursuit's episode where none is given
FOVEA_HALF_ANGLE = np.radians(7.5)
MAX_DISTANCE_BL = 100.0  # the farthest start and flight distance, BL
MAX_OTHERS = 8  # distractors and passers at most, each
MAX_GLANCES = 4  # looks per frame at most
RENDER_MODES = (None, "rgb_array", "retina")


def check_render_mode(render_mode: str | None) -> str | None:
    if render_mode not in RENDER_MODES:
        raise ValueError(f"render_mode must be None, 'rgb_array' or 'retina', got "
                         f"{render_mode!r}")
    return render_mode


def pursuit_params(duration: float, start_distance_bl: tuple[float, float] | None,
                   bearing_deg: tuple[float, float], flee_distance_bl: float,
                   prey_speed: float, distractors: int, passers: int, occluders: bool,
                   glances: int, water: dict | None) -> PursuitParams:
    """The pursuit's arguments (see the env's docstring), each checked as it enters: a bad
    one is a ValueError of one line naming it (the duration and the water are checked by the
    batch they make)."""
    length = fish_body().length
    metres = (1.0 / length, 4.0 / length)  # 1-4 m, BL
    bearing = check_range("bearing_deg", bearing_deg, -360.0, 360.0, "deg")
    if bearing[1] - bearing[0] > 360.0:
        raise ValueError(f"bearing_deg must span at most 360 deg, got {shown(bearing_deg)}")
    return PursuitParams(
        duration=duration,
        start_distance_bl=check_range(
            "start_distance_bl", metres if start_distance_bl is None else start_distance_bl,
            1.0, MAX_DISTANCE_BL, "BL"),
        bearing_deg=bearing,
        flee_distance_bl=check_number("flee_distance_bl", flee_distance_bl, 0.0,
                                      MAX_DISTANCE_BL, "BL", low_open=True),
        prey_speed=check_number("prey_speed", prey_speed, 0.0, 1.0),
        distractors=check_integer("distractors", distractors, 0, MAX_OTHERS),
        passers=check_integer("passers", passers, 0, MAX_OTHERS),
        occluders=check_flag("occluders", occluders),
        glances=check_integer("glances", glances, 1, MAX_GLANCES), water=water)


MAX_FRAMES = 8  # frames stacked at most


def pursuit_observer(view: ObserverView, sensors: list | None, oracle: bool, eyes: bool = True
                     ) -> tuple[PursuitObserver, gym.spaces.Dict]:
    """The observation's sensors (default :func:`default_sensors`, without the retina when
    ``eyes`` is False; plus the privileged ``prey`` with ``oracle``) and one observer's space
    (with ``glance`` when a frame has more than one look)."""
    if not check_flag("eyes", eyes) and sensors is not None:
        raise ValueError("eyes: false leaves the retina out of the default sensors; give "
                         "sensors or eyes, not both")
    if sensors is None:
        sensors = default_sensors(view.retina) if eyes else default_sensors(view.retina)[1:]
    if check_flag("oracle", oracle):
        sensors = [*sensors, PreyPosition(PREY)]
    observer = PursuitObserver(view, sensors)
    space = observer.single_space
    glances = view.worlds.params.glances
    if glances > 1:  # how many looks are left before the body moves
        space = gym.spaces.Dict({**space.spaces, "glance": gym.spaces.Box(
            0.0, float(glances - 1), (1,), np.float32)})
    return observer, space


class FrameStack:
    """The last ``frames`` readings of a ``Dict`` observation's images (its uint8 entries of
    three dimensions), stacked along their channels, the oldest first: (H, W, frames C), or
    (frames C, H, W) for the entries named in ``first`` (channel-first images, e.g. the
    ``pixels`` sensor's). A reset fills the stack with its first reading. The rest of the
    observation is as read."""

    def __init__(self, frames: int, space: gym.spaces.Dict,
                 first: frozenset[str] = frozenset()) -> None:
        self.frames = check_integer("frames", frames, 1, MAX_FRAMES)
        self.images = [key for key, sub in space.spaces.items()
                       if sub.dtype == np.uint8 and len(sub.shape) == 3]
        self.axis = {key: -3 if key in first else -1 for key in self.images}
        self._stacks: dict[str, np.ndarray] = {}

    def space(self, space: gym.spaces.Dict) -> gym.spaces.Dict:
        """One observer's stacked space."""
        stacked = {}
        for key in self.images:
            shape = list(space[key].shape)
            shape[self.axis[key]] *= self.frames
            stacked[key] = gym.spaces.Box(0, 255, tuple(shape), np.uint8)
        return gym.spaces.Dict({**space.spaces, **stacked})

    def __call__(self, obs: dict[str, np.ndarray], fresh: bool) -> dict[str, np.ndarray]:
        """``obs`` (entry -> (B, ...)) with its images stacked; ``fresh``: every episode of
        the batch has just begun."""
        if self.frames == 1:
            return obs
        for key in self.images:
            now, axis = obs[key], self.axis[key]
            if fresh or key not in self._stacks:
                self._stacks[key] = np.concatenate([now] * self.frames, axis=axis)
            else:
                kept = np.delete(self._stacks[key], np.s_[:now.shape[axis]], axis=axis)
                self._stacks[key] = np.concatenate([kept, now], axis=axis)
            obs[key] = self._stacks[key].copy()
        return obs


def observe(observer: PursuitObserver, view: ObserverView, kinematics: Kinematics,
            stack: FrameStack, fresh: bool = False) -> dict[str, np.ndarray]:
    """Entry name -> (B, ...) array: every observer's reading (its images stacked over the
    last frames, ``fresh`` when every episode has just begun), and with glances the looks left
    before its body moves."""
    obs = stack(observer.observe(view, kinematics), fresh)
    worlds = view.worlds
    if worlds.params.glances > 1:
        left = worlds.params.glances - 1 - worlds.glance
        obs["glance"] = left[:, None].astype(np.float32)
    return obs


def in_foveas(points: np.ndarray, positions: np.ndarray, rotations: np.ndarray) -> np.ndarray:
    """(N, K) bool: whether each of world n's points (N, K, 3) m lies within 7.5 deg of both its
    eyes' axes, from the eyes at ``positions`` (N, 2, 3) m turned by ``rotations`` (N, 2, 3,
    3) (row 2 the axis)."""
    direction = points[:, :, None, :] - positions[:, None]  # (N, K, 2, 3)
    cosine = (np.einsum("nkej,nej->nke", direction, rotations[:, :, 2])
              / np.linalg.norm(direction, axis=-1))
    return ~np.any(cosine < np.cos(FOVEA_HALF_ANGLE), axis=-1)


def world_infos(worlds: PursuitWorlds, kinematics: Kinematics, poses, moved: bool
                ) -> dict[str, np.ndarray]:
    """Every world's info (ground truth, for evaluation; see the env's docstring), entry ->
    (N, ...) array, from the eye ``poses`` of :meth:`PursuitWorlds.eye_poses`."""
    positions, rotations = poses
    n, observers = worlds.num_worlds, worlds.observers
    angles = worlds.gaze_angles()
    inside = in_foveas(kinematics.com.reshape(n, worlds.fish, 3), positions, rotations)
    others = DISTRACTOR + worlds.params.distractors
    ranges = [triangulate(a[0, 0], a[1, 0], float(np.linalg.norm(p[0] - p[1])))
              for a, p in zip(angles, positions)]
    return {"target_in_fovea": inside[:, PREY],
            "distractor_in_fovea": inside[:, DISTRACTOR:others].any(axis=1),
            "passer_in_fovea": inside[:, others:].any(axis=1),
            "target_distance": worlds.distance.copy(),
            "gaze": angles.reshape(n, -1),
            "vergence": angles[:, 1, 0] - angles[:, 0, 0],
            "range_estimate": np.array(ranges),
            "time": worlds.time.copy(), "moved": np.full(n, moved),
            "com": kinematics.com[observers].copy(),
            "forward": kinematics.frames[observers, 0].copy()}


def world_info(infos: dict[str, np.ndarray], world: int) -> dict:
    """World ``world``'s info from :func:`world_infos`: flags and scalars as Python's bool
    and float, vectors as arrays."""
    return {key: value[world].copy() if value.ndim > 1 else value[world].item()
            for key, value in infos.items()}


def render_world(worlds: PursuitWorlds, render_mode: str | None, world: int = 0,
                 eyes: Retina = Retina(RetinaParams())) -> np.ndarray | None:
    """World ``world`` in ``render_mode``: ``"retina"`` the observer's two eyes'
    composites side by side (512 x 1024), ``"rgb_array"`` a third-person view (480 x 360)."""
    if render_mode == "retina":
        images = eyes.images(ObserverView(worlds), worlds.core.kinematics())[world]
        return np.concatenate([composite(images[0]), composite(images[1])], axis=1)
    if render_mode == "rgb_array":
        centre = worlds.core.kinematics().com[worlds.rows(world)].mean(axis=0)
        eye = centre + np.array([-1.0, -2.0, 1.2]) * worlds.body_length * 1.5
        camera = Camera(480, 360, 432.0, eye, look_at(eye, centre))
        return camera.render(worlds.scene(world))
    return None
