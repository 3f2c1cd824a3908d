"""A finished run folder back into something that acts (:func:`load`), and ``animat eval``.

``load(run_dir)`` builds the run's learner from its resolved ``config.yaml`` and asks it for an
agent of its ``artefacts.json`` (see :mod:`animat.learners.agents`): the learned tent controller
or its refined abstraction, a macro sequence, a hand-designed MC, PPO's network with its
observation normalisation, the active-vision controller, or a repertoire's skills. The agent has
SB3's ``predict(obs)``, ``reset()``, ``env_id`` and ``env_kwargs``::

    import gymnasium as gym
    import animat  # registers Animat/...
    from .evaluate import load

    agent = load("runs/try")
    env = gym.make(agent.env_id, **agent.env_kwargs)

:func:`evaluate` plays it over seeded start states (by default ones the run never learned from:
:func:`animat.learners.rollout.unseen_seeds`, 1,000,000 + its seed on), optionally filming each
episode with Gymnasium's ``RecordVideo``, and writes ``eval.json`` into the run folder. With
``refine`` k > 1 it plays the agent with the physics step divided by k (``frame_skip`` times k:
the env step, and so what the agent sees and does, unchanged) and writes
``eval_step_over_<k>.json``: a learned figure that moves when the solver is refined is the
solver's, not the animal's. With ``point_start`` it plays from the task's documented start
(no spread, no reset noise: as the paper shows a stunt) and writes ``eval_point_start.json``.
"""

from __future__ import annotations

import copy
from pathlib import Path

import gymnasium as gym
import numpy as np

import animat  # noqa: F401
from animat.learners.agents import SkillSet
from animat.learners.registry import make_learner
from animat.learners.rollout import score_episode, spread, unseen_seeds
from animat.learners.storage.files import CorruptFile, UnsafeFile, read_json
from animat.learners.storage.tree import check_tree, run_folder

from .launch.config import learner_params, load_run_config
from .launch.folders import read_status, write_json
from .launch.lock import RunError
from .launch.shipped import is_shipped_result


def load(run_dir: str | Path, trust_pickles: bool = False):
    """The agent of the finished run in ``run_dir`` (``trust_pickles``: also from an older
    version's pickled checkpoint, which runs its writer's code)."""
    folder = run_folder(run_dir)
    check_tree(folder)  # a folder from someone else: no link or FIFO in it is read
    return _load(folder, trust_pickles)


def _load(folder: Path, trust_pickles: bool):
    """:func:`load` of a folder already checked (:func:`run_folder`, :func:`check_tree`)."""
    status = read_status(folder)
    if status["status"] != "done":
        raise RunError(f"{folder}: the run is {status['status']}; only a finished run can be "
                       "loaded")
    config = load_run_config(folder)  # built below, from its copies
    artefacts = read_json(folder / "artefacts.json")
    learner = _learner(folder, config)
    learner.trust_pickles = trust_pickles
    try:
        return learner.agent(artefacts, folder)
    except (CorruptFile, UnsafeFile, OSError):  # a file of its own, named
        raise
    except (ValueError, TypeError, KeyError) as error:
        raise CorruptFile(folder / "artefacts.json", "not this run's artefacts "
                          f"({' '.join(str(error).split())[:200]})") from None


def _learner(folder: Path, config):
    """The run's learner, built from its config and its own copy of a repertoire
    (:func:`animat.experiments.launch.config.learner_params`)."""
    return make_learner(config.learner.name, config.env.id, config.env.kwargs,
                        learner_params(folder, config, own_files_only=True), config.seed)


def _episodes(agent, seeds: list[int], video: Path | None, prefix: str) -> list[dict]:
    """Score ``agent`` on one seeded episode per seed in its env (filmed into ``video``)."""
    if video is None:
        env = gym.make(agent.env_id, **agent.env_kwargs)
    else:
        env = gym.wrappers.RecordVideo(
            gym.make(agent.env_id, render_mode="rgb_array", **agent.env_kwargs),
            str(video), name_prefix=prefix, episode_trigger=lambda _: True,
            disable_logger=True)
    try:
        return [{"seed": seed, **score_episode(env, agent, seed)} for seed in seeds]
    finally:
        env.close()


def refined(agent, refine: int):
    """A copy of ``agent`` playing in its env with the physics step divided by ``refine``
    (frame_skip times ``refine``); a RunError for an env without a physics step to refine."""
    if refine == 1:
        return agent
    env = gym.make(agent.env_id, **agent.env_kwargs)
    try:
        core = getattr(env.unwrapped, "core", None)
        if core is None or not hasattr(core, "frame_skip"):
            raise RunError(f"--refine: {agent.env_id} has no physics_dt/frame_skip to refine")
        physics_dt, frame_skip = core.system.dt, core.frame_skip
    finally:
        env.close()
    return _with_env_kwargs(agent, {"physics_dt": physics_dt / refine,
                                    "frame_skip": frame_skip * refine}, "--refine")


def from_point_start(agent):
    """A copy of ``agent`` playing from its task's documented start: its placement alone
    (``start_spread="point"``, no ``reset_noise_scale``), the same on every seed; a RunError
    for an env without a start spread."""
    return _with_env_kwargs(agent, {"start_spread": "point", "reset_noise_scale": 0.0},
                            "--point-start")


def _with_env_kwargs(agent, kwargs: dict, option: str):
    """A copy of ``agent`` playing in its env with ``kwargs`` over its own; a RunError naming
    ``option`` for an env that does not take them."""
    changed = copy.copy(agent)
    changed.env_kwargs = {**agent.env_kwargs, **kwargs}
    try:
        gym.make(changed.env_id, **changed.env_kwargs).close()
    except TypeError as error:
        raise RunError(f"{option}: {agent.env_id} does not take {' and '.join(kwargs)} "
                       f"({error})") from None
    return changed


def _played(agent, refine: int, point_start: bool):
    """``agent`` as ``evaluate`` plays it: refined, from the documented start if asked."""
    agent = refined(agent, refine)
    return from_point_start(agent) if point_start else agent


def evaluate(run_dir: str | Path, seeds: list[int] | None = None, episodes: int | None = None,
             video: str | Path | None = None, refine: int = 1, trust_pickles: bool = False,
             point_start: bool = False) -> dict:
    """Play the run's agent on ``seeds`` (default: ``episodes`` start states the run never
    learned from, :func:`~animat.learners.rollout.unseen_seeds`, by default as many as the
    run's own scores are over); returns and writes
    ``eval.json``: the seeds, every episode's figures, and ``metrics`` (``eval/<figure>``
    means with ``_std``) - per skill for a repertoire; with ``refine`` k > 1, at the physics
    step over k, into ``eval_step_over_<k>.json``; with ``point_start``, from the task's
    documented start (one episode unless told), into ``eval_point_start.json``."""
    folder = run_folder(run_dir)
    check_tree(folder)  # a folder from someone else: no link or FIFO in it is read
    config = load_run_config(folder)
    if not seeds:
        count = episodes or (1 if point_start else _learner(folder, config).scored_episodes())
        seeds = unseen_seeds(config.seed, count)
    if refine < 1:
        raise RunError(f"--refine must be at least 1, got {refine}")
    agent = _load(folder, trust_pickles)
    video = Path(video) if video else None
    runs: dict[str, list[dict]] | list[dict]
    metrics: dict[str, dict[str, float]] | dict[str, float]
    if isinstance(agent, SkillSet):
        runs = {name: _episodes(_played(skill, refine, point_start), seeds, video, name)
                for name, skill in agent.agents.items()}
        metrics = {name: spread([_figures(r) for r in rows]) for name, rows in runs.items()}
    else:
        episodes_run = _episodes(_played(agent, refine, point_start), seeds, video,
                                 config.learner.display_name)
        runs, metrics = episodes_run, spread([_figures(r) for r in episodes_run])
    result = {"seeds": seeds, "metric": config.eval.metric, "episodes": runs, "metrics": metrics,
              "physics_step_over": refine, "start": "point" if point_start else "spread"}
    if is_shipped_result(folder):  # a quoted result: compared with what it quotes, not changed
        result["shipped"] = shipped_comparison(folder / result_name(refine, point_start), result)
        return result
    try:  # a read-only run folder (a shared one) is still scored; the CLI says what is missing
        write_json(folder / result_name(refine, point_start), result)
    except OSError as error:
        result["not_written"] = f"{folder / result_name(refine, point_start)}: {error.strerror}"
    return result


def shipped_comparison(path: Path, result: dict) -> str:
    """How ``result`` compares with the shipped scores in ``path`` (the same seeds' metrics, to
    1e-9 relative): a line for ``animat eval`` to print, with the largest move when they differ
    (:func:`largest_move`)."""
    if not path.is_file():
        return f"a shipped result, left as it is ({path.name} not written)"
    shipped = read_json(path)
    if shipped.get("seeds") != result["seeds"]:
        return f"a shipped result, left as it is ({path.name} scores other seeds)"
    old, new = shipped.get("metrics", {}), result["metrics"]
    added = sorted(set(figure_names(new)) - set(figure_names(old)))
    if not set(figure_names(old)) <= set(figure_names(new)):
        return f"DIFFERENT from the shipped {path} (other figures)"
    new = figures_of(new, old)
    if np.allclose(_flat(old), _flat(new), rtol=1e-9, atol=0):
        since = f" (on its figures; added since: {', '.join(added)})" if added else ""
        return f"the same as the shipped {path}{since}"
    name, relative, in_spread = largest_move(old, new)
    if not name:
        return f"DIFFERENT from the shipped {path} (only the spreads over the starts moved)"
    return (f"DIFFERENT from the shipped {path} (the largest move: {name} by {relative:.2g} of "
            f"its value, {in_spread:.2g} of its spread over the starts)")


def figure_names(metrics: dict, prefix: str = "") -> list[str]:
    """A metrics table's figure names, sorted (per skill for a repertoire: ``skill/name``)."""
    return sorted(name for key, value in metrics.items()
                  for name in (figure_names(value, f"{prefix}{key}/") if isinstance(value, dict)
                               else [prefix + key]))


def figures_of(metrics: dict, like: dict) -> dict:
    """``metrics`` cut to the figures ``like`` has (per skill for a repertoire): a re-score
    is compared with a shipped file on the figures it quotes, and a figure added to a task
    since is not a move."""
    return {key: figures_of(metrics[key], value) if isinstance(value, dict) else metrics[key]
            for key, value in like.items()}


def largest_move(shipped: dict, scored: dict) -> tuple[str, float, float]:
    """Of two metrics tables of the same figures (per skill for a repertoire), the mean figure
    that moved most relative to its value: (its name, ``|new - old| / |old|``, and the move
    over the figure's std over the starts, ``<name>_std``; inf where that std is 0 and it
    moved). The second number says whether a move is noise: a learned figure's spread over
    the starts is the scale its comparisons are read at."""
    worst = ("", 0.0, 0.0)
    for name, old, new, std in _mean_figures(shipped, scored):
        relative = abs(new - old) / abs(old) if old else (0.0 if new == old else np.inf)
        in_spread = abs(new - old) / std if std > 0 else (0.0 if new == old else np.inf)
        if (relative, in_spread) > worst[1:]:
            worst = (name, relative, in_spread)
    return worst


def _mean_figures(shipped: dict, scored: dict, prefix: str = ""):
    for key, old in sorted(shipped.items()):
        if isinstance(old, dict):
            yield from _mean_figures(old, scored[key], f"{prefix}{key}/")
        elif not key.endswith("_std"):
            yield (prefix + key, float(old), float(scored[key]),
                   float(shipped.get(f"{key}_std", 0.0)))


def _flat(metrics: dict) -> list[float]:
    """A metrics table's numbers in key order (per skill for a repertoire)."""
    return [x for _, v in sorted(metrics.items())
            for x in (_flat(v) if isinstance(v, dict) else [float(v)])]


def result_name(refine: int, point_start: bool = False) -> str:
    """The file :func:`evaluate` writes into the run folder: ``eval.json``, with
    ``_point_start`` and ``_step_over_<k>`` before its suffix as it was played."""
    return ("eval" + ("_point_start" if point_start else "")
            + (f"_step_over_{refine}" if refine != 1 else "") + ".json")


def _figures(row: dict) -> dict:
    return {k: v for k, v in row.items() if k != "seed"}


def report(result: dict) -> str:
    """Lines: the config's metric (mean ± std, min and max over the seeds), per skill for a
    repertoire."""
    metric, seeds = result["metric"], result["seeds"]
    tables = result["metrics"]
    if "eval/return" in tables:  # one agent
        tables = {"": tables}
    lines = []
    step = result.get("physics_step_over", 1)
    at = f" at the physics step / {step}" if step > 1 else ""
    for name, metrics in tables.items():
        key = metric if metric in metrics else "eval/return"
        rows = result["episodes"][name] if name else result["episodes"]
        values = np.array([row[key.removeprefix("eval/")] for row in rows])
        label = f"{name}: " if name else ""
        lines.append(f"{label}{key} {metrics[key]:.4g} ± {metrics[key + '_std']:.2g} over "
                     f"{len(seeds)} start states (seeds {', '.join(map(str, seeds))}; min "
                     f"{values.min():.4g}, max {values.max():.4g}){at}")
    return "\n".join(lines)
