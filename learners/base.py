"""The one learner interface: every learner is run the same way, with an env id (and its
kwargs), a budget in env steps, a seed and a logger, and can be checkpointed and resumed.

Tags every learner logs, with the global step = env steps consumed: ``eval/return`` and the
task's summary metrics as ``eval/<name>`` (:class:`animat.envs.tasks.base.EpisodeSummary`); anything
else under ``train/``. Hyperparameters go in as text (``hparams``).
"""

from __future__ import annotations

import json
import os
import pickle
import tempfile
import types
import typing
from abc import ABC, abstractmethod
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any, ClassVar

from animat.envs.registration import Timing, timing

from .logger import Logger


@dataclass
class LearnResult:
    """What a run produced: env steps consumed, wall seconds, final metrics (``eval/...``),
    and artefacts (e.g. the best controller as a dict)."""

    env_steps: int
    wall_seconds: float
    metrics: dict[str, float]
    artefacts: dict[str, Any] = field(default_factory=dict)


def episode_timing(env_id: str, env_kwargs: dict | None = None) -> Timing:
    """(dt s, env steps per episode) of the env, from its id and kwargs without building it
    (:func:`animat.envs.registration.timing`; a bad kwarg is the env's own error)."""
    return timing(env_id, env_kwargs)


def episode_steps(env_id: str, env_kwargs: dict | None = None) -> int:
    """Env steps in one episode of the env (its ``episode_steps``), without building it."""
    return timing(env_id, env_kwargs).episode_steps


def check_scoring_budget(budget_env_steps: int, episodes: int, steps: int) -> None:
    """Raise :class:`BudgetError` if ``episodes`` scored episodes of ``steps`` env steps do
    not fit the budget."""
    if budget_env_steps < episodes * steps:
        raise BudgetError(f"{budget_env_steps} is less than the {episodes * steps} env steps "
                          f"scoring takes ({episodes} episodes of {steps})")


def machine_memory() -> int | None:
    """Bytes of memory this process may use: the machine's, or its cgroup's limit where that
    is lower; None where it cannot be read."""
    try:
        total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (AttributeError, ValueError, OSError):
        return None
    try:
        limit = Path("/sys/fs/cgroup/memory.max").read_text().strip()
    except OSError:
        return total
    return min(total, int(limit)) if limit.isdigit() else total


def check_memory(need: int, what: str) -> None:
    """ValueError in one line when ``what`` (e.g. ``nodes 100000000 x 6 actuators``) would
    take more memory (``need`` bytes) than this machine has: a size refused before any work,
    not a MemoryError (or the kernel's OOM killer) in the middle of the run."""
    total = machine_memory()
    if total is not None and need > total:
        raise ValueError(f"{what} would take {need / 2**30:.3g} GiB of memory, more than this "
                         f"machine's {total / 2**30:.3g} GiB")


class BudgetError(ValueError):
    """The run's budget cannot work for this learner (e.g. less than one round): said in one
    line, before anything runs."""


class UntrustedPickle(RuntimeError):
    """A run folder's checkpoint is a pickle (an older version's), and the caller has not said
    it trusts the folder (``--trust-pickles``)."""

    def __init__(self, path: str | Path) -> None:
        super().__init__(f"{path}: a checkpoint of an older version, saved with pickle: loading "
                         f"it can run any code its writer put in it; pass --trust-pickles if you "
                         f"trust where this run folder came from")


class CorruptFile(ValueError):
    """A file of a run folder that cannot be read back (truncated, empty, not what it should
    be): its path and what is wrong, in one line."""

    def __init__(self, path: str | Path, problem: str) -> None:
        super().__init__(f"{path}: {problem} (the file is truncated or corrupt)")


def read_json(path: str | Path) -> dict:
    """A JSON object from ``path``; CorruptFile naming it when it is not one (FileNotFoundError
    when it is missing)."""
    try:
        data = json.loads(Path(path).read_text())
    except json.JSONDecodeError as error:
        raise CorruptFile(path, f"not valid JSON ({error.msg} at line {error.lineno})") from None
    except (UnicodeDecodeError, RecursionError) as error:
        raise CorruptFile(path, f"not JSON text ({type(error).__name__})") from None
    if not isinstance(data, dict):
        raise CorruptFile(path, f"holds a JSON {type(data).__name__}, not an object")
    return data


class Learner(ABC):
    """Base class. Subclasses set ``name`` and implement :meth:`learn`.

    Args:
        env_id: a registered env id, e.g. ``Animat/FishSwim-v0``.
        env_kwargs: keyword arguments for the env.
        params: the learner's own parameters (validated by the subclass).
        seed: the run's seed; everything random derives from it.
        logger: where scalars go.

    ``path_params`` names the params that are file paths (:func:`animat.experiments.launch.config.
    load_config` resolves them against the config file's folder).
    """

    name: ClassVar[str] = "learner"
    # params that name files: a config's relative paths there are relative to its own folder
    path_params: ClassVar[tuple[str, ...]] = ()
    # whether a run folder's pickled checkpoint of an older version may be loaded (its writer's
    # code would run): set by the caller (animat eval/run --trust-pickles), never by a config
    trust_pickles: bool = False

    def __init__(self, env_id: str, env_kwargs: dict | None = None, params: dict | None = None,
                 seed: int = 0, logger: Logger | None = None) -> None:
        self.env_id = env_id
        self.env_kwargs = dict(env_kwargs or {})
        self.params = dict(params or {})
        self.seed = int(seed)
        self.logger = logger or Logger()

    @abstractmethod
    def learn(self, budget_env_steps: int, checkpoint_dir: str | Path | None = None
              ) -> LearnResult:
        """Learn with at most ``budget_env_steps`` env steps. With ``checkpoint_dir``, save
        checkpoints there as it goes and resume from the last one if present."""

    def check_budget(self, budget_env_steps: int) -> None:
        """Raise :class:`BudgetError` if the learner cannot work with this budget (checked
        before any work or file; the default takes any)."""
        return None

    def scored_episodes(self) -> int:
        """How many seeded start states (seeds ``seed`` onward) the run's own scores are
        over."""
        from .rollout import START_STATES

        return START_STATES

    def agent(self, artefacts: dict, folder: Path):
        """What the finished run in ``folder`` (its ``artefacts.json`` given) acts with: an
        agent of :mod:`animat.learners.agents`, built from this learner's config."""
        raise NotImplementedError(f"learner {self.name!r} cannot make an agent of its runs")

    def log_hparams(self) -> None:
        self.logger.text("hparams", json.dumps({"learner": self.name, "env_id": self.env_id,
                                                "env_kwargs": self.env_kwargs,
                                                "params": self.params, "seed": self.seed},
                                               indent=1, default=str))


TMP_SUFFIX = ".tmp"  # atomic_write's temporary files: <name><random>.tmp beside the file


def atomic_write(path: str | Path, write, binary: bool = False, replace: bool = True) -> None:
    """Write a file atomically: ``write(file)`` fills a temporary file beside ``path``, which
    then replaces it, so a reader (or a crash) never sees half a file, and a failure (a full
    disk) leaves no temporary file behind. With ``replace`` False an existing ``path`` is left
    as it is (FileExistsError), even one made meanwhile. An OS error that names no file (a
    write on a full disk) is raised naming ``path``."""
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        handle, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name, suffix=TMP_SUFFIX)
    except OSError as error:  # named by the file it was for, not a temporary name
        raise _naming(error, path, always=True) from None
    try:
        with os.fdopen(handle, "wb" if binary else "w") as file:
            write(file)
            file.flush()
            os.fsync(file.fileno())
        os.chmod(tmp, 0o644)
        if replace:
            os.replace(tmp, path)
        else:
            _place_new(tmp, path)
    except OSError as error:
        raise _naming(error, path) from None
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def _naming(error: OSError, path: Path, always: bool = False) -> OSError:
    """``error``, or the same error (its subclass, by errno) naming ``path`` where it named no
    file (or ``always``): what a one-line report of it needs."""
    if error.errno is None or (error.filename is not None and not always):
        return error
    return OSError(error.errno, error.strerror, str(path))


def _place_new(tmp: str, path: Path) -> None:
    """Give the complete file ``tmp`` the name ``path`` only if no file has it (FileExistsError
    otherwise): a hard link where the file system has them, else claim the name, then fill it."""
    try:
        os.link(tmp, path)  # fails if path exists: no check-then-write race
    except FileExistsError:
        raise
    except OSError:
        os.close(os.open(path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644))
        os.replace(tmp, path)


def save_checkpoint(path: str | Path, payload: Any) -> None:
    """Pickle ``payload`` to ``path`` atomically: an older version's checkpoint format, still
    written for a run begun by it and resumed with ``--trust-pickles`` (new runs write data:
    :mod:`animat.learners.checkpoint_data`)."""
    atomic_write(path, lambda file: pickle.dump(payload, file), binary=True)


def load_checkpoint(path: str | Path) -> Any | None:
    """The payload pickled at ``path``, or None when there is none. Unpickling runs whatever
    code the file's writer put in it: only for folders the caller trusts (``--trust-pickles``)."""
    path = Path(path)
    if not path.exists():
        return None
    with path.open("rb") as file:
        try:
            return _Unpickler(file).load()
        except (pickle.UnpicklingError, EOFError, ValueError, AttributeError, ImportError,
                IndexError, TypeError) as error:
            raise CorruptFile(path, f"cannot be read back ({type(error).__name__}: "
                                    f"{error})") from None


# modules an older version's pickled checkpoints name, and where they are now; a
# "<module>.<Class>" key: that class alone moved out of the module (the rest stayed)
MOVED = {"animat.learners.annealing": "animat.learners.optimizers.annealing",
         "animat.learners.cmaes": "animat.learners.optimizers.cmaes",
         "animat.learners.abstraction": "animat.learners.controllers.abstraction",
         "animat.learners.controller": "animat.learners.controllers.tent",
         "animat.learners.scorers.active_vision": "animat.learners.scorers.pursuit",
         "animat.learners.scorers.behaviours": "animat.learners.scorers.living_world",
         **{f"animat.learners.blackbox.{name}": "animat.learners.blackbox_run"
            for name in ("Phase", "Run")},
         **{f"animat.learners.blackbox.{name}": "animat.learners.controllers.periodic"
            for name in ("ControllerParams", "PeriodicPlayer")},
         "animat.learners.blackbox.ResultFrom": "animat.learners.controllers.report"}


class _Unpickler(pickle.Unpickler):
    """Reads checkpoints written before the code moved under ``animat.`` (their ``learners.*``
    and ``envs.*`` classes are this package's) and before the learners' rooms (:data:`MOVED`)."""

    def find_class(self, module: str, name: str):
        if module.split(".")[0] in ("envs", "learners", "experiments"):
            module = f"animat.{module}"
        module = MOVED.get(f"{module}.{name}", MOVED.get(module, module))
        return super().find_class(module, name)


def unknown_params(params: dict, allowed: set[str], learner: str) -> None:
    """Raise ValueError naming parameters a learner does not take (``learner``: its name, or
    a description such as ``learner 'annealing'``)."""
    extra = sorted(set(params) - allowed)
    if extra:
        who = learner if learner.startswith("learner ") else f"learner {learner!r}"
        raise ValueError(f"{who} does not take parameter(s) {extra}; "
                         f"it takes {sorted(allowed)}")


def _kind_ok(value, kind) -> bool:
    """Whether ``value`` fits the annotation ``kind`` (int, float, bool, str, dict, list,
    tuple, Any, and unions with None of these)."""
    if kind is Any:
        return True
    if typing.get_origin(kind) in (typing.Union, types.UnionType):
        return any(_kind_ok(value, k) for k in typing.get_args(kind))
    if kind is type(None):
        return value is None
    if kind is bool:
        return isinstance(value, bool)
    if kind is int:
        return isinstance(value, int) and not isinstance(value, bool)
    if kind is float:
        return isinstance(value, (int, float)) and not isinstance(value, bool)
    origin = typing.get_origin(kind) or kind
    if origin in (list, tuple):
        return isinstance(value, (list, tuple))
    return isinstance(value, origin)


_KIND_NAMES = {int: "an integer", float: "a number", bool: "true or false", str: "a string",
               dict: "a mapping", list: "a list", tuple: "a list"}


def _kind_name(kind) -> str:
    if typing.get_origin(kind) in (typing.Union, types.UnionType):
        return " or ".join("null" if k is type(None) else _kind_name(k)
                           for k in typing.get_args(kind))
    return _KIND_NAMES.get(typing.get_origin(kind) or kind, getattr(kind, "__name__", str(kind)))


def typed_params(cls: type, values: dict, owner: str):
    """A frozen params dataclass ``cls`` from a config mapping: unknown names and values of
    the wrong kind are refused in one line naming ``owner`` (e.g. ``learner 'annealing'``) and
    the field; integers given for floats become floats; ``cls.__post_init__`` then checks
    ranges."""
    unknown_params(values, {f.name for f in fields(cls)}, owner)
    hints = typing.get_type_hints(cls)
    converted = {}
    for name, value in values.items():
        if not _kind_ok(value, hints[name]):
            raise ValueError(f"{owner}: {name} must be {_kind_name(hints[name])}, got {value!r}")
        converted[name] = float(value) if hints[name] is float else value
    try:
        return cls(**converted)
    except ValueError as error:
        raise ValueError(f"{owner}: {error}") from None


class Scorer(Learner):
    """A learner that only scores a fixed controller over seeded episodes (learns nothing):
    its budget must hold those episodes, :meth:`scored_episodes` of the env's length."""

    def check_budget(self, budget_env_steps: int) -> None:
        check_scoring_budget(budget_env_steps, self.scored_episodes(),
                             episode_steps(self.env_id, self.env_kwargs))
