"""Every registered learner on a tiny budget; annealing reproducibility and resume."""

from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

from animat.learners.base import episode_timing
from animat.learners.controllers.abstraction import AbstractController
from animat.learners.controllers.periodic import PeriodicPlayer
from animat.learners.controllers.report import ResultFrom
from animat.learners.controllers.tent import play
from animat.learners.logger import Logger, MemorySink
from animat.learners.optimizers import annealing
from animat.learners.registry import LEARNERS, make_learner
from animat.learners.rollout import BatchEvaluator
from animat.learners.storage.files import CorruptFile
from tests.support.faults import Crash, CrashingSink

ENV = "Animat/FishSwim-v0"
TINY_ENV = {"duration": 0.5}  # 10 env steps per episode, 40 per candidate (4 start states)
TINY = {
    "annealing": ({"chains": 8, "nodes": 4}, 960),
    "cmaes": ({"popsize": 8, "nodes": 4}, 960),
    "ppo": ({"n_envs": 4, "n_steps": 16, "batch_size": 32, "n_epochs": 1, "eval_every": 64,
             "policy_kwargs": "dict(net_arch=[16])"}, 128),
    "handmc": ({}, 40),
    "basic_training": ({"regimen": [
        {"name": "swim", "env_id": "Animat/FishSwim-v0", "env_kwargs": {"duration": 0.5},
         "params": {"nodes": 4, "period": 0.5}},
        {"name": "turn", "env_id": "Animat/FishTurn-v0", "env_kwargs": {"duration": 0.5},
         "params": {"nodes": 4, "period": None}}], "annealing": {"chains": 8}}, 1920),
    "macro": ({"chains": 8, "slots": 2}, 960),
    "active_vision": ({"episodes": 2}, 20),
    "behaviours": ({"episodes": 2}, 20),
    "stroke": ({"chains": 8, "prefix": [{"skill": "move_forward", "duration": 0.2}]}, 960),
    "stroke_cmaes": ({"popsize": 8, "prefix": [{"skill": "move_forward", "duration": 0.2}]},
                     960),
    "steering": ({"episodes": 2}, 20),
    "switching": ({"chains": 4, "start_states": 2}, 160),
    "switching_coordinate": ({"start_states": 2}, 160),
    "stunt_table": ({"chains": 4, "start_states": 2}, 160),
    "stunt_table_coordinate": ({"start_states": 2}, 160),
    "macro_triggered": ({"chains": 4, "start_states": 2, "slots": 2, "flight_slots": 2}, 160),
}
DOLPHIN_REPERTOIRE = str(Path(__file__).resolve().parents[2] / "repertoires" / "dolphin.json")
FISH_REPERTOIRE = str(Path(__file__).resolve().parents[2] / "repertoires" / "fish_reactive.json")


@pytest.fixture(scope="module")
def tiny_repertoire(tmp_path_factory):
    """A repertoire learned on a tiny budget (the basic-training learner's own output)."""
    folder = tmp_path_factory.mktemp("repertoire")
    params, budget = TINY["basic_training"]
    make_learner("basic_training", ENV, TINY_ENV, params, seed=0).learn(budget, folder)
    return folder / "repertoire.json"


def test_every_registered_learner_has_a_tiny_setting():
    assert set(TINY) == set(LEARNERS)


@pytest.mark.parametrize("name", sorted(LEARNERS))
def test_learner_runs_on_a_tiny_budget_and_logs_the_shared_tags(name, tmp_path,
                                                                tiny_repertoire):
    params, budget = TINY[name]
    env_id, tags = ENV, ("eval/return", "eval/speed_bl_per_s")
    if name == "macro":
        params = {**params, "repertoire": str(tiny_repertoire)}
        env_id, tags = "Animat/FishReach-v0", ("eval/return", "eval/final_distance_bl")
    if name == "basic_training":
        tags = ("eval/return",)
    if name in ("steering", "switching", "switching_coordinate"):  # they need turns to both sides
        params = {**params, "repertoire": FISH_REPERTOIRE}
        env_id, tags = "Animat/FishReach-v0", ("eval/return", "eval/reached")
    if name.startswith(("stroke", "stunt_table", "macro_triggered")):
        params = {**params, "repertoire": DOLPHIN_REPERTOIRE}
        env_id, tags = "Animat/DolphinSomersault-v0", ("eval/return",
                                                        "eval/flight_rotation_deg")
    if name == "active_vision":
        env_id, tags = "Animat/FishPursuit-v0", ("eval/return", "eval/fovea_fraction",
                                                 "eval/distance_closed_bl")
    if name == "behaviours":
        env_id, tags = "Animat/MarineWorld-v0", ("eval/return", "eval/food_eaten",
                                                 "eval/obstacle_collisions")
    sink = MemorySink()
    learner = make_learner(name, env_id, TINY_ENV, params, seed=0, logger=Logger([sink]))
    result = learner.learn(budget, checkpoint_dir=tmp_path)
    assert 0 < result.env_steps <= budget
    for tag in tags:
        assert np.isfinite(result.metrics[tag])
        steps = [step for step, _ in sink.series(tag)]
        assert steps and steps == sorted(steps) and max(steps) <= budget
    assert any(tag == "hparams" for tag, _, _ in sink.texts)


def test_unknown_learner_and_parameter_are_named():
    with pytest.raises(ValueError, match="unknown learner 'nope'"):
        make_learner("nope", ENV)
    with pytest.raises(ValueError, match="temprature"):
        make_learner("annealing", ENV, TINY_ENV, {"temprature": 1.0})


def _anneal(budget, checkpoint_dir=None, seed=3, **params):
    return _learn("annealing", budget, checkpoint_dir, seed, chains=8, **params)


def _learn(name, budget, checkpoint_dir=None, seed=3, logger_sink=None, **params):
    sink = logger_sink or MemorySink()
    learner = make_learner(name, ENV, TINY_ENV, {"nodes": 4, "checkpoint_every": 1, **params},
                           seed=seed, logger=Logger([sink]))
    return learner.learn(budget, checkpoint_dir), sink


REFINE = {"period": 0.5, "nodes": 10}
REFINE_BY = {"annealing": {"chains": 8, "refine": {"share": 1 / 3, "threshold": 0.3,
                                                   "step_size": 0.1}},
             "cmaes": {"popsize": 8, "refine": {"share": 1 / 3, "threshold": 0.3,
                                                "sigma0": 0.1}}}


def test_annealing_is_bit_for_bit_reproducible():
    (a, sink_a), (b, sink_b) = _anneal(3200), _anneal(3200)
    assert a.metrics == b.metrics
    assert a.artefacts["controller"] == b.artefacts["controller"]
    untimed = [[r for r in sink.records if not r[0].startswith("time/")]  # but the clock's
               for sink in (sink_a, sink_b)]
    assert untimed[0] == untimed[1] and len(untimed[0]) < len(sink_a.records)
    c, _ = _anneal(3200, seed=4)
    assert c.artefacts["controller"] != a.artefacts["controller"]


def test_annealing_resumed_from_a_checkpoint_ends_identical(tmp_path):
    whole, _ = _anneal(3200)
    _anneal(400, tmp_path)  # interrupted half way (its checkpoint stays)
    resumed, _ = _anneal(3200, tmp_path)
    assert resumed.env_steps == whole.env_steps
    assert resumed.metrics == whole.metrics
    assert resumed.artefacts["controller"] == whole.artefacts["controller"]


@pytest.mark.parametrize("name", ["annealing", "cmaes"])
def test_refinement_searches_the_abstraction_with_its_share_of_the_budget(name):
    result, sink = _learn(name, 4800, **REFINE, **REFINE_BY[name])
    alone, _ = _learn(name, 3200, **REFINE, **{k: v for k, v in REFINE_BY[name].items()
                                              if k != "refine"})
    learned, refined = result.artefacts["learned_metrics"], result.artefacts["abstraction_metrics"]
    assert learned == alone.metrics  # phase 1 had exactly the budget less refine's share
    assert 4800 - 320 < result.env_steps <= 4800 and refined["refined"]
    assert refined["parameters"] < result.artefacts["parameters"] == 60
    # refining starts by scoring the truncated abstraction itself: it can only improve on it
    assert refined["eval/return"] >= refined["before_refining"]["eval/return"]
    assert result.metrics["eval/return"] == max(learned["eval/return"], refined["eval/return"])
    result_from = ResultFrom(result.artefacts["result_from"])  # its value, as result.json holds
    assert type(result.artefacts["result_from"]) is str
    assert result_from is (ResultFrom.LEARNED if result.metrics == learned
                           else ResultFrom.REFINED_ABSTRACTION)
    steps = [step for step, _ in sink.series("eval/return")]
    assert steps[-1] == result.env_steps and any(step > 3240 for step in steps)  # refining
    # the stored abstraction plays back to the score reported for it
    player = PeriodicPlayer(AbstractController.from_dict(result.artefacts["abstraction"]), 0.5)
    evaluator = BatchEvaluator(ENV, TINY_ENV, 8, seed=3)
    returns, _ = evaluator.evaluate(player.actions(evaluator.dt, evaluator.steps)[None])
    assert returns[0] == pytest.approx(refined["eval/return"], abs=1e-9)


def test_the_reported_controller_plays_back_without_building_the_env(tmp_path, monkeypatch):
    params, budget = TINY["annealing"]
    learner = make_learner("annealing", ENV, TINY_ENV, {**params, "period": 0.5}, seed=0)
    artefacts = learner.learn(budget).artefacts
    monkeypatch.setattr(gym, "make", lambda *a, **k: pytest.fail("an env was built"))
    assert episode_timing(ENV, TINY_ENV) == (0.05, 10)
    learned = learner.agent(artefacts, tmp_path).actions
    assert learned.shape == (10, 6) and artefacts["result_from"] == ResultFrom.LEARNED
    old = {k: v for k, v in artefacts.items() if k != "result_from"}  # before result_from
    np.testing.assert_array_equal(learner.agent(old, tmp_path).actions, learned)
    refined = {**artefacts, "result_from": "refined abstraction"}  # as result.json holds it
    expected = PeriodicPlayer(AbstractController.from_dict(artefacts["abstraction"]), 0.5)
    np.testing.assert_array_equal(learner.agent(refined, tmp_path).actions,
                                  expected.actions(0.05, 10))
    for value, written in (("refined", '"refined"'), (None, "null"), (1, "1")):
        with pytest.raises(CorruptFile) as error:
            learner.agent({**artefacts, "result_from": value}, tmp_path)
        assert str(error.value).startswith(
            f"{tmp_path / 'artefacts.json'}: result_from is {written}, not one of "
            f'"learned", "refined abstraction"'), str(error.value)
        assert "\n" not in str(error.value)


@pytest.mark.parametrize("name", ["annealing", "cmaes"])
@pytest.mark.parametrize("crash_after", [2000, 3200, 4000])  # learning, at the switch, refining
def test_refinement_resumed_from_a_checkpoint_ends_identical(tmp_path, name, crash_after):
    params = {**REFINE, **REFINE_BY[name], "checkpoint_every": 3}
    whole, _ = _learn(name, 4800, **params)
    with pytest.raises(Crash):
        _learn(name, 4800, tmp_path, logger_sink=CrashingSink(crash_after), **params)
    resumed, _ = _learn(name, 4800, tmp_path, **params)
    assert resumed.env_steps == whole.env_steps
    assert resumed.metrics == whole.metrics
    assert resumed.artefacts["abstraction"] == whole.artefacts["abstraction"]


def test_bad_refinement_settings_are_named():
    with pytest.raises(ValueError, match="stepsize"):
        make_learner("annealing", ENV, TINY_ENV, {"refine": {"stepsize": 0.1}})
    with pytest.raises(ValueError, match="threshold in"):
        make_learner("cmaes", ENV, TINY_ENV, {"refine": {"share": 0.2, "threshold": 2}})
    with pytest.raises(ValueError, match=r"share in \(0, 1\)"):
        make_learner("annealing", ENV, TINY_ENV, {"refine": {"share": 1.5}})
    with pytest.raises(ValueError, match="refine.env_steps is gone: give refine.share"):
        make_learner("annealing", ENV, TINY_ENV, {"refine": {"env_steps": 3200}})


def test_annealing_accepts_downhill_and_cools():
    params = annealing.AnnealingParams(chains=4, moves_per_temperature=1, cooling=0.5,
                                       schedule="stages")
    state = annealing.init(params, np.full(3, 0.5), seed=0)
    x, state = annealing.ask(params, state)
    state = annealing.tell(params, state, x, np.ones(4))
    proposals, state = annealing.ask(params, state)
    assert not np.array_equal(proposals, x) and np.all((0 <= proposals) & (proposals <= 1))
    told = annealing.tell(params, state, proposals, np.zeros(4))  # all downhill
    np.testing.assert_array_equal(told.x, proposals)
    assert np.all(told.energy == 0.0) and told.temperature == pytest.approx(
        0.5 * params.initial_temperature)



def test_annealing_rejects_a_diverged_move_and_refuses_a_diverged_start():
    params = annealing.AnnealingParams(chains=3)
    state = annealing.init(params, np.full(2, 0.5), seed=0)
    x, state = annealing.ask(params, state)
    with pytest.raises(ValueError, match="starting points' energies must be finite"):
        annealing.tell(params, state, x, np.array([1.0, np.nan, 1.0]))
    state = annealing.tell(params, state, x, np.ones(3))
    proposals, state = annealing.ask(params, state)
    told = annealing.tell(params, state, proposals, np.array([np.nan, np.inf, 0.0]))
    np.testing.assert_array_equal(told.x[:2], x[:2])
    np.testing.assert_array_equal(told.x[2], proposals[2])
    assert told.energy.tolist() == [1.0, 1.0, 0.0]


def test_a_round_with_a_diverged_candidate_logs_the_finite_best_and_counts_the_diverged():
    from animat.learners.blackbox_run import Phase, Run, log_round

    sink = MemorySink()
    run = Run([Phase(params=None, state=None)], env_steps=100)
    returns = np.array([np.nan, -2.0, -1.0])
    metrics = {"reached": np.array([np.nan, 0.0, 1.0])}
    run.phases[0].track(np.eye(3), returns, metrics)
    log_round(Logger([sink]), run, returns, metrics, {})
    assert run.phases[0].best["return"] == -1.0
    assert sink.series("eval/return") == [(100, -1.0)]
    assert sink.series("eval/reached") == [(100, 1.0)]
    assert sink.series("train/diverged") == [(100, 1.0)]
    assert sink.series("time/fps") == []  # no wall time yet, no rate
    run.wall, timed = 4.0, MemorySink()
    log_round(Logger([timed]), run, returns, metrics, {})
    assert timed.series("time/fps") == [(100, 25.0)]  # env steps per wall second
    every = Run([Phase(params=None, state=None)], env_steps=200)
    every.phases[0].track(np.eye(1), np.array([np.nan]), {"reached": np.array([np.nan])})
    assert every.phases[0].best is None
    log_round(Logger([sink]), every, np.array([np.nan]), {"reached": np.array([np.nan])}, {})
    assert sink.series("train/diverged")[-1] == (200, 1.0)
    assert sink.series("eval/return") == [(100, -1.0)]

@pytest.mark.parametrize("budget", [960, 4800])
def test_annealing_cools_to_its_stop_temperature_as_the_budget_ends(budget):
    """The budget's schedule (``train/temperature``: what the next round runs at): every
    round cooler than the one before, the last one the budget affords at ``min_temperature``
    (a run's refinement anneals again over its own share); the fixed stages' schedule of the
    same settings is still warm when the budget ends."""
    cold = annealing.AnnealingParams().min_temperature
    _, sink = _anneal(budget)
    temperatures = [value for _, value in sink.series("train/temperature")]
    assert len(temperatures) == budget // (8 * 40)  # every round the budget affords
    assert temperatures[0] == annealing.AnnealingParams().initial_temperature
    assert np.all(np.diff(temperatures[:-1]) < 0)  # the first move round at T0, cooler on
    assert temperatures[-2] == pytest.approx(cold)  # the last move round runs at T_min
    _, sink = _anneal(budget, schedule="stages")
    assert sink.series("train/temperature")[-1][1] > 100 * cold
    _, sink = _learn("annealing", 3 * 1920, chains=8, period=0.5,
                     refine={"share": 1 / 3, "threshold": 0.3})
    series = [value for _, value in sink.series("train/temperature")]
    restart = next(k for k in range(1, len(series)) if series[k] > series[k - 1])
    for phase in (series[:restart], series[restart:]):
        assert phase[-2] == pytest.approx(cold)


def test_a_resumed_budget_schedule_takes_a_larger_budget_at_once(tmp_path):
    """Stopped at a budget's end and resumed with twice the budget, the schedule re-plans:
    the next round runs warmer than the stop temperature and the last at it again."""
    cold = annealing.AnnealingParams().min_temperature
    _anneal(1920, tmp_path)
    _, sink = _anneal(3840, tmp_path)
    temperatures = [value for _, value in sink.series("train/temperature")]
    assert temperatures[0] > 10 * cold and temperatures[-2] == pytest.approx(cold)


def test_a_budget_schedule_needs_a_stop_temperature_below_its_start():
    with pytest.raises(ValueError, match="must be below initial_temperature"):
        annealing.AnnealingParams(initial_temperature=1e-5)
    with pytest.raises(ValueError, match="schedule must be one of"):
        annealing.AnnealingParams(schedule="fast")
    annealing.AnnealingParams(initial_temperature=1e-5, schedule="stages")  # stops at once


def test_ppo_resumes_from_its_checkpoint(tmp_path):
    params, _ = TINY["ppo"]
    params = {**params, "checkpoint_every": 64}
    first = make_learner("ppo", ENV, TINY_ENV, params, seed=0).learn(128, tmp_path)
    assert (tmp_path / "ppo" / "latest.json").exists() and first.env_steps == 128
    resumed = make_learner("ppo", ENV, TINY_ENV, params, seed=0).learn(256, tmp_path)
    assert resumed.env_steps == 256  # continued from 128, not from 0


def test_candidates_are_scored_over_several_start_states():
    """The same actions from 4 seeded starts: the score is their mean, the spread is reported,
    and all 4 episodes are charged."""
    size = gym.make(ENV).action_space.shape[0]
    actions = np.random.default_rng(0).uniform(-1, 1, (2, 10, size)).astype(np.float32)
    several = BatchEvaluator(ENV, TINY_ENV, 2, seed=5, num_starts=4)
    returns, metrics = several.evaluate(actions)
    assert several.env_steps == 2 * 4 * 10
    singles = [BatchEvaluator(ENV, TINY_ENV, 2, seed=5 + k, num_starts=1).evaluate(actions)
               for k in range(4)]
    np.testing.assert_allclose(returns, np.mean([r for r, _ in singles], axis=0), rtol=1e-12)
    speeds = np.array([m["speed_bl_per_s"] for _, m in singles])
    np.testing.assert_allclose(metrics["speed_bl_per_s_std"], speeds.std(axis=0), rtol=1e-9)
    assert np.all(metrics["speed_bl_per_s_std"] > 0)  # the starts do differ


@pytest.mark.parametrize("name, params, message", [
    ("annealing", {"chains": "lots"}, "learner 'annealing': chains must be an integer, got 'lots'"),
    ("annealing", {"period": "1s"}, "learner 'annealing': period must be a number or null"),
    ("cmaes", {"sigma0": -1.0}, "learner 'cmaes': CMAESParams: need popsize >= 2, sigma0 > 0"),
    ("handmc", {"speed": 2.0}, "learner 'handmc': speed must be in [0, 1]"),
    ("ppo", {"n_steps": 0}, "learner 'ppo': n_steps: Input should be greater than or equal to 1"),
    ("ppo", {"normalize": "yes"}, "learner 'ppo': normalize: use true, false or a mapping"),
    ("macro", {}, "learner 'macro': needs params.repertoire"),
    ("basic_training", {"annealing": 3}, "learner 'basic_training': annealing must be a mapping"),
    ("basic_training", {"regimen": [{"name": "t", "env_id": "Animat/FishTurn-v0",
                                     "learner": "ppo"}]},
     "regimen skill 't': learner 'ppo' is not one of ['annealing', 'cmaes']"),
])
def test_every_learner_checks_its_typed_params_in_one_line(name, params, message):
    with pytest.raises(ValueError) as error:
        make_learner(name, ENV, TINY_ENV, params)
    assert str(error.value).startswith(message), str(error.value)
    assert "\n" not in str(error.value)


def test_a_checkpoint_written_before_the_animat_namespace_still_loads(tmp_path):
    """Run folders from before the move under ``animat.`` pickled ``learners.*`` classes."""
    import pickle

    from animat.learners.blackbox_run import Run
    from animat.learners.storage.pickles import load_checkpoint

    old = pickle.dumps(Run(env_steps=640, rounds=2), protocol=0).replace(  # text opcodes
        b"animat.learners.", b"learners.")
    assert b"animat." not in old
    (tmp_path / "checkpoint.pkl").write_bytes(old)
    run = load_checkpoint(tmp_path / "checkpoint.pkl")
    assert isinstance(run, Run) and run.env_steps == 640 and run.rounds == 2


def test_a_checkpoint_naming_the_classes_where_they_were_still_loads(tmp_path):
    """Pickles of an older version name the black-box run's classes in ``blackbox`` and the
    scorers' params in ``scorers.active_vision`` and ``scorers.behaviours``: :data:`MOVED`
    finds them where they are now, with or without ``animat.``."""
    import pickle

    from animat.learners.blackbox_run import Phase, Run
    from animat.learners.controllers.periodic import ControllerParams
    from animat.learners.scorers.living_world import BehavioursParams
    from animat.learners.scorers.pursuit import PursuitEvalParams
    from animat.learners.storage.pickles import load_checkpoint

    payload = {"run": Run([Phase(annealing.AnnealingParams(), None, start={"eval/return": 1.0})],
                          env_steps=640, rounds=2),
               "own": ControllerParams(nodes=5), "pursuit": PursuitEvalParams(episodes=3),
               "world": BehavioursParams(episodes=2)}
    now = pickle.dumps(payload, protocol=0)  # text opcodes: "c<module>\n<name>\n"
    for prefix in (b"animat.learners.", b"learners."):
        old = now
        for new, was in ((b"blackbox_run", b"blackbox"), (b"controllers.periodic", b"blackbox"),
                         (b"scorers.pursuit", b"scorers.active_vision"),
                         (b"scorers.living_world", b"scorers.behaviours")):
            assert b"animat.learners." + new + b"\n" in old
            old = old.replace(b"animat.learners." + new + b"\n", prefix + was + b"\n")
        assert b"blackbox_run" not in old and b"scorers.pursuit" not in old
        (tmp_path / "checkpoint.pkl").write_bytes(old)
        assert load_checkpoint(tmp_path / "checkpoint.pkl") == payload


def test_a_pickle_naming_the_repertoire_module_still_loads(tmp_path):
    """Pickles of an older version name the repertoire's and basic training's classes in
    ``repertoire`` (and later the repertoire's in ``skills.repertoire``): :data:`MOVED` finds
    them where they are now, with or without ``animat.``."""
    import pickle

    from animat.learners.controllers.repertoire import Skill
    from animat.learners.skills.basic_training import BasicTrainingParams
    from animat.learners.storage.pickles import load_checkpoint

    payload = {"skill": Skill("swim", None, {"duration": 4.0}),
               "params": BasicTrainingParams(regimen="dolphin")}
    now = pickle.dumps(payload, protocol=0)  # text opcodes: "c<module>\n<name>\n"
    for prefix in (b"animat.learners.", b"learners."):
        old = now
        for new in (b"controllers.repertoire", b"skills.basic_training"):
            assert b"animat.learners." + new + b"\n" in old
            old = old.replace(b"animat.learners." + new + b"\n", prefix + b"repertoire\n")
        assert b"skills" not in old and b"controllers" not in old
        (tmp_path / "checkpoint.pkl").write_bytes(old)
        assert load_checkpoint(tmp_path / "checkpoint.pkl") == payload
    in_skills = now.replace(b"controllers.repertoire", b"skills.repertoire")  # its older room
    (tmp_path / "checkpoint.pkl").write_bytes(in_skills)
    assert load_checkpoint(tmp_path / "checkpoint.pkl") == payload


def test_the_hand_mc_plays_back_without_building_the_env(tmp_path, monkeypatch):
    """handmc's agent reads the task and the clock off the id and kwargs
    (:func:`animat.envs.registration.task_of`, ``timing``)."""
    env = gym.make("Animat/FishTurn-v0", duration=0.5, angle_deg=45.0)
    task, dt, steps = env.unwrapped.task, env.unwrapped.dt, env.unwrapped.episode_steps
    env.close()
    learner = make_learner("handmc", "Animat/FishTurn-v0", {"duration": 0.5, "angle_deg": 45.0})
    monkeypatch.setattr(gym, "make", lambda *a, **k: pytest.fail("an env was built"))
    agent = learner.agent({"speed": 0.5}, tmp_path)
    assert agent.actions.shape == (steps, 6)
    expected = play(task.hand_controller(speed=0.5), dt, steps)
    np.testing.assert_array_equal(agent.actions, expected)


def test_a_regimen_skill_may_be_learned_by_cmaes_and_says_so(tmp_path):
    """A skill naming ``learner: cmaes`` is learned by CMA-ES with its own params (the run's
    shared annealing params are not its), and its repertoire entry records the learner."""
    from animat.learners.controllers.repertoire import Repertoire

    regimen = [{"name": "turn", "env_id": "Animat/FishTurn-v0", "env_kwargs": TINY_ENV,
                "learner": "cmaes", "params": {"nodes": 4, "period": None, "popsize": 8}},
               {"name": "swim", "env_id": "Animat/FishSwim-v0", "env_kwargs": TINY_ENV,
                "params": {"nodes": 4, "period": 0.5}}]
    learner = make_learner("basic_training", ENV, TINY_ENV,
                           {"regimen": regimen, "annealing": {"chains": 8}})
    learner.learn(1920, tmp_path)
    skills = Repertoire.load(tmp_path / "repertoire.json").skills
    assert skills["turn"].metadata["learner"] == "cmaes"
    assert skills["swim"].metadata["learner"] == "annealing"
    assert skills["turn"].metadata["env_steps"] == 960 - 960 % (8 * 40)
