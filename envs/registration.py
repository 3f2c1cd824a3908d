"""Every env id, in one table: :data:`ENVS` maps each ``Animat/...`` id to its entry points
and registered keyword arguments, and :func:`register` gives them to Gymnasium (called once,
by importing :mod:`animat.envs`). :func:`register_env` adds a user's id of a registered task
and body to the table and to Gymnasium (``animat.envs.register_env``; docs/tutorials/extending.md).

The fish's locomotion ids and the dolphin's tasks run on the batched core
(:mod:`animat.envs.core`, a native vector env each), the pursuit on its own batched core of
worlds (:mod:`animat.envs.world.pursuit.worlds`, a native vector env too); the living world
is a single env.

:func:`timing` gives an id's clock (``dt`` and ``episode_steps``) from these kwargs and the
user's, without building the env; :func:`body_of`, :func:`task_of`, :func:`water_of` and
:func:`start_spread_of` its body, task, water and start spread, :func:`action_size_of` its
action's length, and :func:`recorded_kwargs` its
kwargs with the water and the start spread written out.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, NamedTuple

import gymnasium as gym
from gymnasium.envs.registration import load_env_creator

if TYPE_CHECKING:
    from .bodies.spec import BodySpec
    from .core.env_args import BodyArgs
    from .physics.system import Water
    from .tasks.base import Task
    from .tasks.start import StartSpread

CORE: dict[str, str] = {"entry_point": "animat.envs.core.env:BodyEnv",
        "vector_entry_point": "animat.envs.core.env:BodyVectorEnv"}
FISH_ENVS = {"Animat/FishSwim-v0": {"task": "swim"}, "Animat/FishTurn-v0": {"task": "turn"},
             "Animat/FishReach-v0": {"task": "reach"}}
# The dolphin's world: a water surface at z = 0, skin friction for its Reynolds number (C_f
# 0.0028 at Re 1e7: 0.5 rho C_f = 1.4 kg/m^3), and a step within its stability bound. The pool
# is the base water: a user's water={...} changes its fields, it does not replace the pool. Its
# water model is the default (reactive) one, as the fish's; water={"model": "resistive"} the
# paper's.
DOLPHIN_KWARGS: dict[str, Any] = {"body": "dolphin",
                                  "base_water": {"surface_z": 0.0, "friction_coefficient": 1.4},
                                  "physics_dt": 0.05 / 80, "frame_skip": 80}
# The stunts weigh the controller's effort (mu1) a tenth of the fish's: a 5 Hz fluke stroke
# costs ten times a 3 Hz fish's tail beat in E_u, which would otherwise outweigh the stunt.
STUNT_WEIGHTS = {"mu1": 1e-5}
DOLPHIN_ENVS: dict[str, dict[str, Any]] = {
    "Animat/DolphinForward-v0": {"task": "dolphin_forward"},
    "Animat/DolphinTurn-v0": {"task": "dolphin_turn"},
    "Animat/DolphinArc-v0": {"task": "dolphin_arc"},
    "Animat/DolphinSpin-v0": {"task": "dolphin_spin"},
    "Animat/DolphinLeap-v0": {"task": "leap", "reward_weights": STUNT_WEIGHTS},
    "Animat/DolphinNoseBall-v0": {"task": "ball", "part": "nose",
                                  "reward_weights": STUNT_WEIGHTS},
    "Animat/DolphinTailBall-v0": {"task": "ball", "part": "tail",
                                  "reward_weights": STUNT_WEIGHTS},
    "Animat/DolphinSomersault-v0": {"task": "somersault", "reward_weights": STUNT_WEIGHTS},
    "Animat/DolphinBellyFlop-v0": {"task": "belly_flop", "reward_weights": STUNT_WEIGHTS},
}
PURSUIT = {"entry_point": "animat.envs.world.pursuit.env:FishPursuitEnv",
           "vector_entry_point": "animat.envs.world.pursuit.vector:FishPursuitVectorEnv"}
MARINE = "animat.envs.world.marine_env:MarineWorldEnv"
ENVS: dict[str, dict] = {
    **{env_id: {**CORE, "kwargs": kwargs} for env_id, kwargs in FISH_ENVS.items()},
    **{env_id: {**CORE, "kwargs": {**DOLPHIN_KWARGS, **kwargs}}
       for env_id, kwargs in DOLPHIN_ENVS.items()},
    "Animat/FishPursuit-v0": PURSUIT,
    "Animat/MarineWorld-v0": {"entry_point": MARINE},
}


def register() -> None:
    """Give Gymnasium every id of :data:`ENVS` it does not have yet."""
    for env_id, entry in ENVS.items():
        if env_id not in gym.registry:
            gym.register(id=env_id, **entry)


def register_env(env_id: str, task: str, body: str | BodySpec = "fish", **kwargs: Any) -> None:
    """Give Gymnasium ``env_id`` (``"Namespace/Name-v0"``) as a body env of the registered task
    ``task`` and body ``body`` (a name of :data:`animat.envs.bodies.BODIES`, or a spec): the
    project's env shell (:class:`~animat.envs.core.env.BodyEnv`) with its native vector env
    (``gym.make_vec(env_id, num_envs=N)``), entered in :data:`ENVS` as the fish's and the
    dolphin's ids are, so that :func:`timing`, :func:`body_of`, :func:`task_of`, the learners
    that drive the body envs and the launcher's configs take it. ``kwargs``: the env's
    registered defaults (any of the env's arguments, e.g. ``sensors=[...]``, ``duration``,
    ``water``, and the task's own), which a ``gym.make`` or a config's ``env.kwargs`` may
    override.

    The env is built once here (and closed, :func:`built_timing`): what it refuses (an
    argument, a sensor, a step above the body's stability bound) is this call's error, and
    nothing is registered. Refused with a ValueError of one line besides: an id that is not a
    string Gymnasium reads, an id already registered otherwise (the same registration again is
    no change), a task or body name not registered (:func:`animat.envs.register_task`,
    :func:`animat.envs.register_body` first).
    """
    from .bodies import BODIES
    from .bodies.spec import BodySpec as Spec
    from .checks import shown
    from .tasks import TASKS

    if not isinstance(env_id, str):
        raise ValueError(f"register_env: the env id must be a string, got {shown(env_id)}")
    entry = {**CORE, "kwargs": {"task": task, "body": body, **kwargs}}
    if _same(ENVS.get(env_id), entry):
        return
    if env_id in ENVS or env_id in gym.registry:
        raise ValueError(f"register_env: env id {env_id!r} is taken; choose another id")
    if not (isinstance(task, str) and task in TASKS):
        raise ValueError(f"register_env({shown(env_id)}, ...): unknown task {shown(task)}; "
                         f"register it first (animat.envs.register_task) or choose one of "
                         f"{sorted(TASKS)}")
    if not (isinstance(body, Spec) or (isinstance(body, str) and body in BODIES)):
        raise ValueError(f"register_env({shown(env_id)}, ...): unknown body {shown(body)}; "
                         f"register it first (animat.envs.register_body), choose one of "
                         f"{sorted(BODIES)} or pass a BodySpec")
    _register_checked(env_id, entry)


def _same(entry: dict | None, other: dict) -> bool:
    """Whether two :data:`ENVS` entries are equal; not, where their values cannot say (a
    ``BodySpec``'s arrays compare element by element)."""
    try:
        return bool(entry == other)
    except ValueError:
        return False


def _register_checked(env_id: str, entry: dict) -> None:
    """Enter ``entry`` in :data:`ENVS` as ``env_id`` and give it to Gymnasium (:func:`register`),
    then check it by building the env once (:func:`built_timing`); on any refusal both are as
    they were, and Gymnasium's own refusal of the id is a ValueError of one line."""
    ENVS[env_id] = entry
    try:
        register()
    except Exception as error:  # gymnasium's Error for an id it cannot parse
        del ENVS[env_id]
        raise ValueError(f"register_env: {' '.join(str(error).split())}") from None
    try:
        built_timing(env_id)
    except BaseException:
        del ENVS[env_id]
        gym.registry.pop(env_id, None)
        raise


class Timing(NamedTuple):
    """An env's clock: ``dt``, s, the simulated time of one env step (``physics_dt *
    frame_skip``), and ``episode_steps``, env steps an episode (``duration / dt`` rounded, at
    least 1)."""

    dt: float
    episode_steps: int


# gym.make's own keywords, and the arguments whose checks need what the env builds (the body,
# the step and the integrator, the sensors, the task's fit to the body): timing() builds the
# env when the user gives one of these. The water it checks as the env does (BodyArgs.clock).
BUILT_FOR = frozenset({"render_mode", "max_episode_steps", "disable_env_checker", "task", "body",
                       "physics_dt", "sensors", "integrator"})
# single envs of one body batch at the core's default step, whose clock is their duration alone
WORLDS = frozenset({PURSUIT["entry_point"], MARINE})


def timing(env_id: str, env_kwargs: dict | None = None) -> Timing:
    """The clock of ``gym.make(env_id, **env_kwargs)``, without building it: from the registered
    kwargs of :data:`ENVS` and ``env_kwargs`` (these win), with the task's ``default_duration``
    where no ``duration`` is given and the core's ``physics_dt`` and ``frame_skip`` where none
    are. The arguments it reads are checked as the env checks them; where it cannot vouch for
    them (an id not in :data:`ENVS`, an argument of :data:`BUILT_FOR`, a value it refuses) it
    builds the env and reads its clock, so that a bad argument is the env's own one-line
    ValueError (or Gymnasium's error for an unknown id)."""
    given = dict(env_kwargs or {})
    entry = ENVS.get(env_id)
    if entry is not None and not BUILT_FOR & given.keys():
        try:
            reckoned = _reckoned(entry, given)
        except Exception:  # the env decides: its own error, or the clock it builds
            reckoned = None
        if reckoned is not None:
            return reckoned
    return built_timing(env_id, given)


def built_timing(env_id: str, env_kwargs: dict | None = None) -> Timing:
    """The clock of ``gym.make(env_id, **env_kwargs)`` read from the env built (and closed):
    what :func:`timing` reckons without it."""
    env = gym.make(env_id, **(env_kwargs or {}))
    try:
        core: Any = env.unwrapped  # every Animat env has dt and episode_steps
        return Timing(float(core.dt), int(core.episode_steps))
    finally:
        env.close()


def _reckoned(entry: dict, given: dict) -> Timing | None:
    """The clock of the env of ``entry`` (an :data:`ENVS` value) with the user's ``given``
    kwargs over its registered ones: a core env's from its arguments
    (:meth:`~animat.envs.core.env_args.BodyArgs.clock`), a world's from its duration (its
    class's ``default_duration`` where not given); None where the entry point is one it does not
    know; the env's check's ValueError for a bad argument."""
    from .core.env_args import BodyArgs

    kwargs = {**entry.get("kwargs", {}), **given}
    if entry["entry_point"] == CORE["entry_point"]:
        return _clock(*BodyArgs.of_single_env(kwargs).clock())
    if entry["entry_point"] in WORLDS and given.keys() <= {"duration"}:
        world: Any = load_env_creator(entry["entry_point"])  # a world env's class
        default = world.default_duration
        return _world_clock(kwargs.get("duration", default))
    return None


def _world_clock(duration: Any) -> Timing | None:
    """The clock of a world env (:data:`WORLDS`) of ``duration`` s: one body batch at the core's
    default ``physics_dt`` and ``frame_skip``, its duration checked as the batch checks it."""
    from .core.arguments import check_arguments
    from .core.batch import DEFAULT_FRAME_SKIP
    from .physics.system import DEFAULT_DT

    check_arguments(1, DEFAULT_DT, DEFAULT_FRAME_SKIP, duration, 0.0, True, 0.0)
    return _clock(DEFAULT_DT, DEFAULT_FRAME_SKIP, duration)


def _clock(physics_dt: float, frame_skip: int, duration: float) -> Timing | None:
    """``dt = physics_dt * frame_skip`` s and ``max(1, round(duration / dt))`` steps, as the body
    batch computes them; None (build the env) for a ``physics_dt`` or ``duration`` that is not a
    Python number, whose arithmetic could round otherwise."""
    if not all(type(value) in (int, float) for value in (physics_dt, duration)):
        return None
    dt = physics_dt * int(frame_skip)
    return Timing(float(dt), max(1, int(round(duration / dt))))


def body_of(env_id: str, env_kwargs: dict | None = None) -> BodySpec:
    """The body of ``gym.make(env_id, **env_kwargs)``: for an id of the core (the fish's and
    the dolphin's) :func:`animat.envs.bodies.make_body` of its ``body`` (the registered kwargs
    of :data:`ENVS` and ``env_kwargs``, these winning), building no env and checking nothing
    else (:func:`timing` checks the clock's arguments); any other id's env is built and its
    body read."""
    from .bodies import make_body

    arguments = _core_arguments(env_id, env_kwargs)
    if arguments is None:
        return _built_attribute(env_id, env_kwargs, "body")
    return make_body(arguments.body)


def action_size_of(env_id: str, env_kwargs: dict | None = None) -> int:
    """The length of an action of ``gym.make(env_id, **env_kwargs)``: for an id of the core
    its body's actuators and, with ``fins``, its fins (:meth:`BodySpec.action_size`), its
    arguments checked as :func:`timing` checks them, building no env; any other id's env is
    built and its action space read."""
    arguments = _core_arguments(env_id, env_kwargs)
    if arguments is None:
        return gym.spaces.flatdim(_built_attribute(env_id, env_kwargs, "action_space"))
    from .bodies import make_body

    arguments.clock()
    return make_body(arguments.body).action_size(bool(arguments.fins))


def task_of(env_id: str, env_kwargs: dict | None = None) -> Task:
    """The task of ``gym.make(env_id, **env_kwargs)``: for an id of the core
    :func:`animat.envs.tasks.make_task` of its ``task`` with the kwargs the env does not name
    (the task's own), as :func:`body_of` reads them; any other id's env is built and its task
    read."""
    arguments = _core_arguments(env_id, env_kwargs)
    if arguments is None:
        return _built_attribute(env_id, env_kwargs, "task")
    return arguments.make_task()


def water_of(env_id: str, env_kwargs: dict | None = None) -> Water:
    """The water of ``gym.make(env_id, **env_kwargs)``: for an id of the core its ``water``'s
    fields over its ``base_water`` (the dolphin's pool), as the env merges them; for the
    pursuit and the living world their ``water``'s fields; building no env (any other id's env
    is built and its core's water read)."""
    from .physics.system import Water

    arguments = _core_arguments(env_id, env_kwargs)
    if arguments is None:
        if ENVS.get(env_id, {}).get("entry_point") in WORLDS:
            return Water.from_dict((env_kwargs or {}).get("water"))
        core = _built_attribute(env_id, env_kwargs, "core")
        return core.system.water
    return Water.from_dict(arguments.merged_water())


def start_spread_of(env_id: str, env_kwargs: dict | None = None) -> StartSpread | None:
    """The start spread of ``gym.make(env_id, **env_kwargs)`` for an id of the core: its
    ``start_spread`` over its task's own (:mod:`animat.envs.tasks.start`), building no env;
    None for any other id (the pursuit and the world place their own fish)."""
    arguments = _core_arguments(env_id, env_kwargs)
    if arguments is None:
        return None
    return arguments.make_task().start_spread.over(arguments.start_spread)


def recorded_kwargs(env_id: str, env_kwargs: dict | None = None,
                    before: dict | None = None) -> dict:
    """``env_kwargs`` with what the env of them runs in written out, so that they make the same
    env whatever the defaults become: ``water.model`` (:func:`water_of`) and, for an id of the
    core, ``start_spread``'s fields (:func:`start_spread_of`). ``before``: the kwargs that
    stood for a default before it was recorded (e.g. the water of a folder made before folders
    recorded it), used where ``env_kwargs`` names none of them."""
    kwargs, before = dict(env_kwargs or {}), before or {}
    water = kwargs.get("water")
    if not (isinstance(water, dict) and "model" in water):
        named = before.get("water", {}).get("model") or water_of(env_id, kwargs).model
        kwargs["water"] = {**(water if isinstance(water, dict) else {}), "model": named}
    spread = start_spread_of(env_id, {"start_spread": before.get("start_spread"), **kwargs})
    if spread is not None:
        kwargs["start_spread"] = spread.as_dict()
    return kwargs


def _core_arguments(env_id: str, env_kwargs: dict | None) -> BodyArgs | None:
    """The core env's arguments of ``env_id`` (the registered kwargs and ``env_kwargs`` over
    them), or None for an id that is not the core's."""
    from .core.env_args import BodyArgs

    entry = ENVS.get(env_id)
    if entry is None or entry["entry_point"] != CORE["entry_point"]:
        return None
    return BodyArgs.of_single_env({**entry.get("kwargs", {}), **(env_kwargs or {})})


def _built_attribute(env_id: str, env_kwargs: dict | None, name: str) -> Any:
    """``name`` (``body``, ``task``) of the env built (and closed), or of its core; a
    ValueError when it has none."""
    env = gym.make(env_id, **(env_kwargs or {}))
    try:
        unwrapped = env.unwrapped
        value = getattr(unwrapped, name, getattr(getattr(unwrapped, "core", None), name, None))
    finally:
        env.close()
    if value is None:
        raise ValueError(f"{env_id} has no {name} to read")
    return value
