"""Basic training (the paper's Section 4.2): primitive skills learned one by one into a
repertoire.

A regimen of primitive skills (:mod:`animat.learners.skills.regimens`: swims at several
speeds, turns of several angles left and right; the dolphin's turn-down, turn-up, turn-left,
turn-right, move-forward) is learned one skill at a time by annealing (or, where a skill names
``learner: cmaes``, by CMA-ES over the same encoding), each learned controller abstracted by
FFT (and, where its params ask, the abstraction refined), and the abstractions kept in a
repertoire file (:mod:`animat.learners.controllers.repertoire`).
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from animat.envs.registration import recorded_kwargs

from ..agents import OpenLoopAgent, SkillSet
from ..base import Learner, LearnResult, episode_timing
from ..blackbox import AnnealingLearner, CMAESLearner
from ..controllers.abstraction import AbstractController
from ..controllers.repertoire import Repertoire, Skill
from ..logger import Logger
from ..validation import check_drives, typed_params
from .regimens import REGIMENS

# the learners a regimen's skill may name (``learner``; default the paper's annealing)
SKILL_LEARNERS = {"annealing": AnnealingLearner, "cmaes": CMAESLearner}


def skill_learner(spec: dict, annealing: dict, seed: int, threshold: float | None = None,
                  logger: Logger | None = None) -> AnnealingLearner | CMAESLearner:
    """The learner of one regimen skill: its ``learner`` (annealing, with the run's shared
    ``annealing`` params under the skill's own, or CMA-ES with the skill's own), on the skill's
    env (one that learner drives); ``threshold`` the FFT abstraction's."""
    name = spec.get("learner", "annealing")
    if name not in SKILL_LEARNERS:
        raise ValueError(f"regimen skill {spec['name']!r}: learner {name!r} is not one of "
                         f"{sorted(SKILL_LEARNERS)}")
    try:
        check_drives(name, spec["env_id"])
    except ValueError as error:
        raise ValueError(f"regimen skill {spec['name']!r}: {error}") from None
    shared = annealing if name == "annealing" else {}
    params = {**shared, **spec.get("params", {})}
    if threshold is not None:
        params["abstraction_threshold"] = threshold
    return SKILL_LEARNERS[name](spec["env_id"], spec.get("env_kwargs", {}), params, seed,
                                logger)


def learn_skill(spec: dict, env_steps: int, seed: int, threshold: float | None,
                annealing: dict, logger: Logger, checkpoint_dir: Path | None,
                trust_pickles: bool = False) -> Skill:
    """Learn one skill's controller (:func:`skill_learner`), abstract it, and measure what
    abstraction cost (``trust_pickles``: resume from an older version's pickled checkpoint
    too)."""
    learner = skill_learner(spec, annealing, seed, threshold,
                            Logger([_Prefixed(logger, f"skill/{spec['name']}/")]))
    learner.trust_pickles = trust_pickles
    result = learner.learn(env_steps, checkpoint_dir)
    artefacts = result.artefacts
    abstracted = AbstractController.from_dict(artefacts["abstraction"])
    scored, learned = artefacts["abstraction_metrics"], artefacts["learned_metrics"]
    metadata = {
        "task": artefacts["episode"]["task"], "env_id": spec["env_id"],
        # the water and the start spread it learned in, written out
        "env_kwargs": recorded_kwargs(spec["env_id"], spec.get("env_kwargs", {})),
        "objective": "E = -return (paper Eq. 1)",
        "learner": spec.get("learner", "annealing"),
        "duration": artefacts["episode"]["duration"],
        "learned_E": -learned["eval/return"], "abstracted_E": -scored["eval/return"],
        "parameters_learned": result.artefacts["parameters"],
        "parameters_abstracted": abstracted.num_parameters,
        "coefficients_kept": abstracted.num_coefficients,
        "learned_metrics": {k: v for k, v in learned.items() if k != "eval/return"},
        "abstracted_metrics": {k: v for k, v in scored.items() if k.startswith("eval/")
                               and k != "eval/return"},
        "env_steps": result.env_steps, "refined": scored["refined"],
        "threshold": scored.get("threshold", threshold),
    }
    return Skill(spec["name"], abstracted, metadata)


class _Prefixed:
    """A sink that forwards to a logger with a tag prefix."""

    def __init__(self, logger: Logger, prefix: str) -> None:
        self.logger, self.prefix = logger, prefix

    def scalar(self, tag: str, value: float, step: int) -> None:
        self.logger.scalar(self.prefix + tag, value, step)

    def text(self, tag: str, text: str, step: int) -> None:
        self.logger.text(self.prefix + tag, text, step)

    def close(self) -> None:
        pass


@dataclass(frozen=True)
class BasicTrainingParams:
    """regimen: [{name, env_id, env_kwargs, params}], or the name of a shipped one
    (:data:`~animat.learners.skills.regimens.REGIMENS`: ``fish``, ``fish_paper``,
    ``dolphin``, ``dolphin_paper``, ...; None: the fish's); threshold: the FFT
    threshold (None: the most compact abstraction within 10%); annealing: annealing params
    shared by all skills; output: a path the repertoire is also written to (None: only the
    run folder's ``checkpoints/repertoire.json``), refused if it exists unless ``force``."""

    regimen: list | str | None = None
    threshold: float | None = None
    annealing: dict = field(default_factory=lambda: {"chains": 64})
    output: str | None = None
    force: bool = False


def _check_regimen(regimen: list, owner: str) -> None:
    """ValueError naming ``owner`` unless ``regimen`` is a non-empty list of skills, each a
    mapping with a ``name`` (given once: the repertoire keeps one skill a name) and an
    ``env_id``."""
    if not regimen:
        raise ValueError(f"{owner}: regimen must name at least one skill, got {regimen!r}")
    names = []
    for k, spec in enumerate(regimen):
        if not (isinstance(spec, dict) and isinstance(spec.get("name"), str) and spec["name"]
                and isinstance(spec.get("env_id"), str)):
            raise ValueError(f"{owner}: regimen skill {k} must be a mapping with a name and "
                             f"an env_id, got {spec!r:.80}")
        if spec["name"] in names:
            raise ValueError(f"{owner}: regimen names skill {spec['name']!r} twice; a "
                             f"repertoire keeps one skill a name")
        if not isinstance(spec.get("learner", "annealing"), str):
            raise ValueError(f"{owner}: regimen skill {spec['name']!r}: learner must be a "
                             f"name, got {spec['learner']!r:.60}")
        for key in ("env_kwargs", "params"):
            if not isinstance(spec.get(key, {}), dict):
                raise ValueError(f"{owner}: regimen skill {spec['name']!r}: {key} must be a "
                                 f"mapping, got {spec[key]!r:.60}")
        names.append(spec["name"])


class BasicTrainingLearner(Learner):
    """Learns every skill of ``regimen`` (default: the fish's) with an equal share of the
    budget and writes ``repertoire.json`` into the checkpoint folder (and, asked, to
    ``output``: never over a file that exists unless ``force``).

    Params: ``regimen`` (list of {name, env_id, env_kwargs, params}, or ``"fish"``,
    or a name in :data:`~animat.learners.skills.regimens.REGIMENS`), ``threshold`` (FFT;
    default: the most compact abstraction within 10% of the learned objective),
    ``annealing`` (annealing parameters shared by all skills), ``output`` (a second copy's
    path, relative to the config's folder), ``force`` (let ``output`` replace a file).
    The env id it is given is not used: each skill names its own."""

    name = "basic_training"
    path_params = ("output",)

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        own = typed_params(BasicTrainingParams, self.params, f"learner {self.name!r}")
        if isinstance(own.regimen, str) and own.regimen not in REGIMENS:
            raise ValueError(f"learner {self.name!r}: regimen {own.regimen!r} is not one of "
                             f"{sorted(REGIMENS)} (or give a list of skills)")
        regimen = own.regimen if own.regimen is not None else "fish"
        self.regimen = REGIMENS[regimen] if isinstance(regimen, str) else regimen
        _check_regimen(self.regimen, f"learner {self.name!r}")
        self.threshold = None if own.threshold is None else float(own.threshold)
        self.annealing = dict(own.annealing)
        self.output, self.force = own.output, bool(own.force)
        # every skill's settings are checked before any learning
        self._skill_learners = [skill_learner(spec, self.annealing, self.seed)
                                for spec in self.regimen]

    def agent(self, artefacts: dict, folder: Path) -> SkillSet:
        """Each skill of the repertoire the run wrote (its run folder's copy, which a later
        run cannot overwrite; or the one its artefacts name, if it is in the folder: a folder
        may be someone else's), played open loop in its own env."""
        path = Path(folder) / "checkpoints" / "repertoire.json"
        if not os.path.lexists(path):
            named = os.path.realpath(Path(folder, artefacts.get("repertoire") or "."))
            if not named.startswith(os.path.realpath(folder) + os.sep):
                raise FileNotFoundError(f"{folder}: the run wrote no repertoire file in its "
                                        "folder")
            path = Path(named)
        agents = {}
        for name, skill in Repertoire.load(path).skills.items():
            env_id, kwargs = skill.metadata["env_id"], skill.metadata.get("env_kwargs", {})
            dt, steps = episode_timing(env_id, kwargs)
            agents[name] = OpenLoopAgent(skill.controller, dt, steps, env_id, kwargs)
        return SkillSet(agents)

    def check_budget(self, budget_env_steps: int) -> None:
        """Each skill gets an equal share; its learner must be able to use it. An ``output``
        that exists is refused here, before any learning, unless ``force``."""
        if self.output and not self.force and Path(self.output).exists():
            raise ValueError(f"output {self.output} exists; a run does not overwrite it "
                             f"(choose another path, or let it: animat run --force, i.e. "
                             f"learner.params.force: true)")
        for learner in self._skill_learners:
            learner.check_budget(budget_env_steps // len(self.regimen))

    def learn(self, budget_env_steps: int, checkpoint_dir: str | Path | None = None
              ) -> LearnResult:
        self.check_budget(budget_env_steps)
        start = time.perf_counter()
        self.log_hparams()
        folder = Path(checkpoint_dir) if checkpoint_dir else None
        share = budget_env_steps // len(self.regimen)
        repertoire, used = Repertoire(), 0
        for k, spec in enumerate(self.regimen):
            skill_dir = folder / spec["name"] if folder else None
            skill = learn_skill(spec, share, self.seed + k, self.threshold, self.annealing,
                                self.logger, skill_dir, self.trust_pickles)
            repertoire.add(skill)
            used += skill.metadata["env_steps"]
            self.logger.scalar("eval/return", -skill.metadata["abstracted_E"], used)
        if folder:
            repertoire.save(folder / "repertoire.json")  # the run's own copy, always
        if self.output:
            try:
                repertoire.save(self.output, replace=self.force)
            except FileExistsError:
                kept = f"; the run's copy is {folder / 'repertoire.json'}" if folder else ""
                raise ValueError(f"output {self.output} was made while the run learned, and "
                                 f"is left as it is{kept}") from None
        output = self.output or (folder / "repertoire.json" if folder else None)
        metrics = {"eval/return": float(np.mean([-s.metadata["abstracted_E"]
                                                 for s in repertoire.skills.values()]))}
        return LearnResult(env_steps=used, wall_seconds=time.perf_counter() - start,
                           metrics=metrics, artefacts={
                               "repertoire": str(output) if output else None,
                               "skills": {n: s.metadata for n, s in repertoire.skills.items()}})

