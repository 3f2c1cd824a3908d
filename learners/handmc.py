"""The hand-designed motor controllers as a learner that learns nothing, so that they stand in
every comparison, evaluated by the same protocol as the learners."""

from __future__ import annotations

import time
from pathlib import Path

from learners.base import Learner, LearnResult, unknown_params
from learners.controller import play
from learners.rollout import START_STATES, BatchEvaluator


class HandMCLearner(Learner):
    """Plays the task's hand-designed MC (:meth:`envs.tasks.Task.hand_controller`): swim ->
    swim-MC at ``speed`` (default 1), ease-in included (scored from t = 0 like every learned
    controller); turn -> the turn-MC for the env's angle and direction. Uses one episode from
    each start state."""

    name = "handmc"

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        unknown_params(self.params, {"speed", "start_states"}, self.name)
        self.speed = float(self.params.get("speed", 1.0))

    def learn(self, budget_env_steps: int, checkpoint_dir: str | Path | None = None
              ) -> LearnResult:
        start = time.perf_counter()
        evaluator = BatchEvaluator(self.env_id, self.env_kwargs, num_envs=1, seed=self.seed,
                                   num_starts=self.params.get("start_states", START_STATES))
        if budget_env_steps < evaluator.episode_cost:
            raise ValueError(f"budget too small: scoring needs {evaluator.episode_cost} env steps")
        self.log_hparams()
        actuation = evaluator.task.hand_controller(speed=self.speed)
        actions = play(actuation, evaluator.dt, evaluator.steps)[None]
        returns, metrics = evaluator.evaluate(actions)
        result = {"eval/return": float(returns[0]),
                  **{f"eval/{k}": float(v[0]) for k, v in metrics.items()}}
        self.logger.scalars(result, evaluator.env_steps)
        return LearnResult(env_steps=evaluator.env_steps,
                           wall_seconds=time.perf_counter() - start, metrics=result,
                           artefacts={"speed": self.speed})
