"""The hand-designed motor controllers as a learner that learns nothing, so that they stand in
every comparison, evaluated by the same protocol as the learners."""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

from animat.envs.registration import task_of, timing, water_of

from ..agents import OpenLoopAgent
from ..base import LearnResult, Scorer
from ..controllers.tent import play
from ..rollout import START_STATES, BatchEvaluator
from ..validation import typed_params


@dataclass(frozen=True)
class HandMCParams:
    """speed: the swim-MC's speed in [0, 1]; start_states: seeded starts it is scored over."""

    speed: float = 1.0
    start_states: int = START_STATES

    def __post_init__(self) -> None:
        if not 0.0 <= self.speed <= 1.0 or self.start_states < 1:
            raise ValueError("speed must be in [0, 1] and start_states >= 1")


class HandMCLearner(Scorer):
    """Plays the task's hand-designed MC (:meth:`animat.envs.tasks.base.Task.hand_controller`):
    swim ->
    swim-MC at ``speed`` (default 1), ease-in included (scored from t = 0 like every learned
    controller); turn -> the turn-MC for the env's angle and direction; each calibrated for the
    env's water (:func:`animat.envs.motor.fish.calibrated`, the dolphin's
    :func:`animat.envs.motor.dolphin.dolphin_calibrated`). Uses one episode from each start
    state."""

    name = "handmc"

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.own = typed_params(HandMCParams, self.params, f"learner {self.name!r}")
        self.speed = self.own.speed

    def agent(self, artefacts: dict, folder) -> OpenLoopAgent:
        """The task's MC at the run's ``speed``, played open loop (no env built)."""
        dt, steps = timing(self.env_id, self.env_kwargs)
        task = task_of(self.env_id, self.env_kwargs)
        model = water_of(self.env_id, self.env_kwargs).model
        speed = float(artefacts.get("speed", self.speed))
        return OpenLoopAgent(task.hand_controller(speed=speed, model=model), dt, steps,
                             self.env_id, self.env_kwargs)

    def scored_episodes(self) -> int:
        return int(self.own.start_states)

    def learn(self, budget_env_steps: int, checkpoint_dir: str | Path | None = None
              ) -> LearnResult:
        self.check_budget(budget_env_steps)
        start = time.perf_counter()
        evaluator = BatchEvaluator(self.env_id, self.env_kwargs, num_envs=1, seed=self.seed,
                                   num_starts=self.own.start_states)
        self.log_hparams()
        model = water_of(self.env_id, self.env_kwargs).model
        actuation = evaluator.task.hand_controller(speed=self.speed, model=model)
        actions = play(actuation, evaluator.dt, evaluator.steps)[None]
        returns, metrics = evaluator.evaluate(actions)
        result = {"eval/return": float(returns[0]),
                  **{f"eval/{k}": float(v[0]) for k, v in metrics.items()}}
        self.logger.scalars(result, evaluator.env_steps)
        return LearnResult(env_steps=evaluator.env_steps,
                           wall_seconds=time.perf_counter() - start, metrics=result,
                           artefacts={"speed": self.speed})
