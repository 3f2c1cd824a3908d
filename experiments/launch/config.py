"""Experiment configs: YAML validated against typed schemas (pydantic, unknown keys forbidden).

Top-level keys: ``env`` (``id``, ``kwargs``), ``learner`` (``name``, ``params``), ``budget``
(``env_steps``), ``seed``, ``eval``, ``logging``, and ``tune`` (the search space of
``animat tune``). ``--set key.path=value`` overrides any field
(the value is read as YAML: ``3``, ``0.5``, ``true``, ``[1, 2]``, ``{a: 1}``). A bad config or
override raises :class:`ConfigError`, whose one-line message names the file, the field path and
what is wrong (:mod:`.config_yaml` reads the YAML).
"""

from __future__ import annotations

import copy
import os
from pathlib import Path
from typing import Any

import yaml
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from .config_yaml import ConfigError, read_yaml
from .lock import RunError

# The seeds every learner takes: NumPy's legacy generator (SB3's PPO seeds it) and pycma take
# no seed above 2**32 - 1.
MAX_SEED = 2**32 - 1
# The largest budget a config may ask for: years of simulation at any speed this simulator
# reaches, and below 2**53, so that the learners' float arithmetic on budgets (a refinement's
# share, rounds of a population) stays exact.
MAX_ENV_STEPS = 10**15
class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", validate_assignment=True)


class EnvConfig(_Strict):
    id: str
    kwargs: dict[str, Any] = Field(default_factory=dict)

    @field_validator("id")
    @classmethod
    def _registered(cls, value: str) -> str:
        import gymnasium as gym

        import animat  # noqa: F401  (registers Animat/*)

        if value not in gym.registry:
            known = sorted(k for k in gym.registry if k.startswith("Animat/"))
            raise ValueError(f"unknown env id {value!r}; registered: {', '.join(known)} "
                             f"(one your module registers: animat --import MODULE ...)")
        return value


class LearnerConfig(_Strict):
    """``name`` (a learner of :data:`animat.learners.registry.LEARNERS` as the table is when
    the config is read: the package's, or one the reading process registered), ``params`` (its
    own), ``label``: what run folders and ``animat compare`` call this variant (default: the
    name), e.g. to set an ablation of a learner beside the learner itself."""

    name: str
    params: dict[str, Any] = Field(default_factory=dict)
    label: str | None = Field(default=None, pattern=r"^[A-Za-z0-9][A-Za-z0-9_.+-]*$")

    @property
    def display_name(self) -> str:
        return self.label or self.name

    @field_validator("name")
    @classmethod
    def _registered(cls, value: str) -> str:
        from animat.learners.registry import LEARNERS

        if value not in LEARNERS:
            raise ValueError(f"unknown learner {value!r}; choose one of {sorted(LEARNERS)} "
                             f"(one your module registers: animat --import MODULE ...)")
        return value


class BudgetConfig(_Strict):
    env_steps: int = Field(gt=0, le=MAX_ENV_STEPS)


class EvalConfig(_Strict):
    """How results are compared: ``metric`` (the headline tag), ``threshold`` (for "env steps
    to reach it"; optional)."""

    metric: str = "eval/return"
    threshold: float | None = Field(default=None, allow_inf_nan=False)


class LoggingConfig(_Strict):
    tensorboard: bool = True
    csv: bool = True
    progress: bool = True


class SearchDimension(_Strict):
    """One hyperparameter's range for ``animat tune``: ``low``/``high`` (numbers; integers
    for an integer parameter), ``log`` (sample on a log scale), ``step`` (a grid), or
    ``choices`` (a list)."""

    low: int | float | None = None
    high: int | float | None = None
    log: bool = False
    step: int | float | None = None
    choices: list[Any] | None = None

    def model_post_init(self, __context) -> None:
        low, high = self.low, self.high
        ranged = low is not None and high is not None
        if ranged == (self.choices is not None):
            raise ValueError("give either low and high, or choices")
        if low is not None and high is not None and not low < high:
            raise ValueError(f"need low < high, got {low} and {high}")
        if self.log and low is not None and high is not None and low <= 0:
            raise ValueError("a log range needs low > 0")
        if self.log and self.step is not None:
            raise ValueError("give log or step, not both")


class TuneConfig(_Strict):
    """``space``: {config field path (e.g. ``learner.params.cooling``): its range};
    ``direction``: whether ``eval.metric`` is to be maximised or minimised."""

    space: dict[str, SearchDimension]
    direction: str = Field(default="maximize", pattern=r"^(maximize|minimize)$")


class ExperimentConfig(_Strict):
    env: EnvConfig
    learner: LearnerConfig
    budget: BudgetConfig
    seed: int = Field(default=0, ge=0, le=MAX_SEED)
    eval: EvalConfig = Field(default_factory=EvalConfig)
    logging: LoggingConfig = Field(default_factory=LoggingConfig)
    tune: TuneConfig | None = None


def apply_override(data: dict, override: str, source: str) -> None:
    """Apply ``key.path=value`` to the raw config dict in place."""
    if "=" not in override:
        raise ConfigError(source, "", f"override {override!r} must look like key.path=value")
    path, raw = override.split("=", 1)
    keys = path.strip().split(".")
    if not all(keys):
        raise ConfigError(source, path, f"override {override!r} has an empty key")
    value = read_yaml(raw, source, path.strip())
    node = data
    for key in keys[:-1]:
        child = node.get(key)
        if child is None:
            child = node[key] = {}
        if not isinstance(child, dict):
            raise ConfigError(source, path, f"{key!r} is not a mapping, cannot set {path}")
        node = child
    node[keys[-1]] = value


def validate(data: Any, source: str) -> ExperimentConfig:
    """The typed config, or ConfigError naming the first problem."""
    if not isinstance(data, dict):
        raise ConfigError(source, "", "the config must be a YAML mapping")
    try:
        config = ExperimentConfig.model_validate(data)
    except ValidationError as error:
        first = error.errors()[0]
        path = ".".join(str(p) for p in first["loc"])
        message = first["msg"].removeprefix("Value error, ")
        if first["type"] == "extra_forbidden":
            message = "unknown key"
        elif first["type"] == "missing":
            message = "required field is missing"
        raise ConfigError(source, path, message) from None
    from animat.learners.validation import check_drives

    try:
        check_drives(config.learner.name, config.env.id)
    except ValueError as error:
        raise ConfigError(source, "env.id", str(error)) from None
    return config


def learner_params(folder: Path, config, own_files_only: bool = False) -> dict:
    """The run's learner params; a repertoire it composes from is the run folder's own copy
    (``checkpoints/repertoire.json``) where it kept one (a resumed run, a finished one), so
    that neither the current directory nor a later rewrite of the repertoire file changes
    what the run is. ``own_files_only``: the folder may be someone else's (resumed,
    re-scored), so its config reaches no file outside it: no ``output`` is written (the
    run's repertoire stays in its folder) and a repertoire it kept no copy of is a RunError."""
    params = dict(config.learner.params)
    copy = Path(folder) / "checkpoints" / "repertoire.json"
    if "repertoire" in params and os.path.lexists(copy):
        params["repertoire"] = str(copy)
    elif "repertoire" in params and own_files_only:
        raise RunError(f"{folder}: learner.params.repertoire names {params['repertoire']}, "
                       "outside the run folder, which a resumed or re-scored run does not "
                       "read (it reads its own copy, checkpoints/repertoire.json, which this "
                       "folder lacks); run its config again instead")
    if own_files_only:
        params.pop("output", None)
        params.pop("force", None)
    return params


def check_buildable(config: ExperimentConfig, source: str, params: dict | None = None) -> None:
    """Build the env and the learner once (cheap: no learning, no files written) so that an env
    keyword, a learner parameter, a budget or an eval metric that cannot be used stops the run
    before any work, as ConfigError on ``env.kwargs``, ``learner.params``,
    ``budget.env_steps`` or ``eval.metric`` (one the env reports: :func:`reported_metrics`).
    ``params``: the learner params to build with (default the config's)."""
    from animat.learners.registry import make_learner
    from animat.learners.validation import BudgetError

    try:
        metrics = reported_metrics(config.env.id, config.env.kwargs)
    except Exception as error:  # whatever the env's constructor refuses is its kwargs' fault
        raise ConfigError(source, "env.kwargs", _said(error)) from None
    try:
        make_learner(config.learner.name, config.env.id, config.env.kwargs,
                     config.learner.params if params is None else params,
                     config.seed).check_budget(config.budget.env_steps)
    except BudgetError as error:
        raise ConfigError(source, "budget.env_steps", str(error)) from None
    except Exception as error:
        raise ConfigError(source, "learner.params", _said(error)) from None
    if config.eval.metric not in metrics:
        shown = ", ".join(m for m in metrics if not m.endswith("_std"))
        raise ConfigError(source, "eval.metric", f"{config.eval.metric} is not a metric "
                          f"{config.env.id} reports; it reports {shown} (each also as "
                          f"<name>_std, its spread over the episodes)")


def reported_metrics(env_id: str, env_kwargs: dict) -> tuple[str, ...]:
    """The ``eval/`` metrics a run of the env reports: ``eval/return`` and each figure of the
    env's episode summary (``env.unwrapped.episode_summary()``, the task's means and final
    figures, or a world's own), each also with ``_std``, read off the summary of an episode
    just reset (the env built, reset once and closed; its errors are its kwargs')."""
    import gymnasium as gym

    env = gym.make(env_id, **env_kwargs)
    try:
        _, info = env.reset(seed=0)
        unwrapped: Any = env.unwrapped  # every env of this project sums its episodes up
        summary = unwrapped.episode_summary()
        summary.update(info)
        names = ["return", *summary.summary()]
    finally:
        env.close()
    return tuple(f"eval/{name}{end}" for name in names for end in ("", "_std"))


def _said(error: Exception) -> str:
    """What a refusal says, on one line: a ValueError's or TypeError's message as it is (they
    are written for the user), a KeyError's key, else ``Type: message`` (an error the code
    did not word: its type tells where it came from)."""
    if isinstance(error, KeyError) and error.args:
        text = str(error.args[0])
    elif isinstance(error, ValueError | TypeError | OSError):
        text = str(error)
    else:
        text = f"{type(error).__name__}: {error}"
    return " ".join(text.split()) or type(error).__name__


def migrate(data: dict) -> None:
    """Bring an older config's fields up to date in place (before any override): a refinement
    budget in env steps (``refine.env_steps``) becomes its share of the file's budget."""
    learner, budget = data.get("learner"), data.get("budget")
    params = learner.get("params") if isinstance(learner, dict) else None
    refine = params.get("refine") if isinstance(params, dict) else None
    budget = budget.get("env_steps") if isinstance(budget, dict) else None
    if (isinstance(refine, dict) and type(refine.get("env_steps")) is int
            and type(budget) is int and 0 < refine["env_steps"] < budget):
        refine["share"] = refine.pop("env_steps") / budget


def resolve_paths(data: dict, base: Path) -> None:
    """Make the learner's file params (its ``path_params``: a repertoire, an output) absolute
    and free of links in place (the user's own files, where a folder on the way may be a
    link), a relative one taken from ``base``; other fields are left for validation."""
    from animat.learners.registry import LEARNERS

    learner = data.get("learner")
    if not isinstance(learner, dict) or learner.get("name") not in LEARNERS:
        return
    params = learner.get("params")
    if not isinstance(params, dict):
        return
    for name in LEARNERS[learner["name"]].path_params:
        value = params.get(name)
        if isinstance(value, str) and value:
            params[name] = os.path.realpath(base / value)


def _config_text(path: str | Path, follow_links: bool) -> str:
    """The text of the config file ``path``, read as :func:`animat.learners.storage.files.
    read_text` reads a file: a regular file of at most a config's bound (UnsafeFile naming it
    otherwise); ``follow_links``: a file the user named, its links resolved first (a run
    folder's own is never followed). ConfigError where it cannot be read (missing,
    unreadable, not UTF-8)."""
    from animat.learners.storage.files import CorruptFile, read_text

    try:
        return read_text(path, "config", follow_links=follow_links)
    except OSError as error:
        raise ConfigError(str(path), "", f"cannot read the file: {error.strerror}") from None
    except CorruptFile:  # what read_text finds corrupt: bytes that are not UTF-8
        raise ConfigError(str(path), "", "not a text file (not UTF-8)") from None


def config_from_data(data: Any, source: str, base: Path,
                     overrides: list[str] | None = None) -> ExperimentConfig:
    """The typed config of ``data`` (a config's mapping, as its YAML reads; left unchanged),
    brought up to date (:func:`migrate`), its learner's relative file params taken from
    ``base``, then ``overrides`` applied (their paths taken from the current directory) and
    validated; ConfigError naming ``source`` (the file, or what stands for it) and the field.
    Not built: :func:`check_buildable` does that."""
    data = copy.deepcopy(data) if isinstance(data, dict) else data
    if isinstance(data, dict):
        migrate(data)
        resolve_paths(data, base)
    for override in overrides or []:
        if not isinstance(data, dict):
            break
        apply_override(data, override, source)
    if isinstance(data, dict):
        resolve_paths(data, Path.cwd())  # what the overrides named, from the shell
    return validate(data, source)


def load_config(path: str | Path, overrides: list[str] | None = None, build: bool = True,
                follow_links: bool = True) -> ExperimentConfig:
    """Read, override and validate a YAML config file; with ``build``, also build its env and
    learner once (:func:`check_buildable`). A relative file path in the learner's params is
    relative to the config file's folder, in an override to the current directory.
    ``follow_links``: whether the file may be reached through a link (a file the user names;
    not a run folder's own, :func:`load_run_config`)."""
    source = str(path)
    data = read_yaml(_config_text(path, follow_links), source)
    config = config_from_data(data, source, Path(path).resolve().parent, overrides)
    if build:  # a run folder's config.yaml builds with its own copy of a repertoire
        check_buildable(config, source, learner_params(Path(path).parent, config))
    return config


# What a run folder made before run folders recorded it ran in: its config.yaml names no water
# model (the reactive water became the default later) and no start spread (each episode then
# started from the task's placement, the point start). Every folder made since names its own
# (record_env).
WATER_BEFORE_RECORDS = "resistive"
START_BEFORE_RECORDS = "point"


def record_env(config: ExperimentConfig, before_records: bool = False) -> ExperimentConfig:
    """``config`` with what its env ran in written out, so that a run folder's config says it
    whatever the defaults become (:func:`animat.envs.registration.recorded_kwargs`: the water
    model and, for an env of the core, the start spread's fields). ``before_records``: a config
    of a folder made before the records, which ran in :data:`WATER_BEFORE_RECORDS` from
    :data:`START_BEFORE_RECORDS` where it names neither. An env not of this project is left
    alone."""
    from animat.envs.registration import ENVS, recorded_kwargs

    if config.env.id not in ENVS:
        return config
    before = {"water": {"model": WATER_BEFORE_RECORDS},
              "start_spread": START_BEFORE_RECORDS} if before_records else None
    kwargs = recorded_kwargs(config.env.id, config.env.kwargs, before)
    return config.model_copy(update={"env": config.env.model_copy(update={"kwargs": kwargs})})


def load_run_config(folder: str | Path, build: bool = False, own_files_only: bool = False
                    ) -> ExperimentConfig:
    """A run folder's ``config.yaml`` with the water and the start it ran in: a folder made
    before run folders recorded them names neither and ran in the resistive water from the
    point start (:func:`record_env`), where its learner learned; with ``build``, checked as
    :func:`load_config` checks it. The file is the folder's own: a link there (or the folder
    a link) is refused (UnsafeFile), never followed out of it; ``own_files_only``: built with
    no file outside the folder (:func:`learner_params`)."""
    from animat.learners.storage.tree import run_folder

    folder = run_folder(folder)  # UnsafeFile if the folder itself is a link
    path = folder / "config.yaml"
    config = record_env(load_config(path, build=False, follow_links=False),
                        before_records=True)
    if build:
        check_buildable(config, str(path), learner_params(folder, config, own_files_only))
    return config


def to_yaml(config: ExperimentConfig) -> str:
    """The resolved config as YAML (what a run folder keeps): every value as it was read,
    ``.inf`` and ``.nan`` included (JSON mode would have written them as null)."""
    return yaml.safe_dump(config.model_dump(mode="python"), sort_keys=False)
