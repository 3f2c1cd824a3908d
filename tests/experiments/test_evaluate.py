"""``load(run_dir)`` and ``animat eval``: every learner's finished run acts again in its env,
and scores what the run reported."""

import json
import shutil

import numpy as np
import pytest
import yaml

from animat.envs.tasks.start import FISH_START, POINT_START
from animat.experiments.evaluate import evaluate, largest_move, load, shipped_comparison
from animat.experiments.figures.repertoire_table import repertoire_markdown, repertoire_rows
from animat.experiments.launch.lock import RunError
from animat.learners.agents import OpenLoopAgent, PolicyAgent, SkillSet
from tests.support.cli import ROOT, TINY, animat, write_config

SWIM = {"id": "Animat/FishSwim-v0", "kwargs": {"duration": 0.5}}
RUNS = {
    "annealing": ({"chains": 8, "nodes": 4, "period": 0.5}, 3200),
    "annealing-refined": ({"chains": 8, "nodes": 4, "period": 0.5,
                           "refine": {"share": 0.5, "threshold": 0.3, "step_size": 0.1}}, 3200),
    "cmaes": ({"popsize": 8, "nodes": 4, "period": 0.5}, 3200),
    "handmc": ({}, 40),
    "ppo": ({"n_envs": 4, "n_steps": 16, "batch_size": 32, "n_epochs": 1, "eval_every": 64,
             "policy_kwargs": "dict(net_arch=[16])"}, 128),
}


def _run(tmp_path, label, env=SWIM, learner=None, params=None, budget=None, metric=None):
    name = learner or label.split("-")[0]
    params, budget = (params, budget) if params is not None else RUNS[label]
    data = {**TINY, "env": env, "learner": {"name": name, "params": params},
            "budget": {"env_steps": budget}}
    if metric:
        data["eval"] = {"metric": metric}
    folder = tmp_path / label
    animat("run", write_config(tmp_path / f"{label}.yaml", data), "--out", folder, "--quiet")
    return folder


@pytest.mark.parametrize("label", sorted(RUNS))
def test_a_loaded_run_scores_what_the_run_reported(tmp_path, label):
    folder = _run(tmp_path, label)
    agent = load(folder)
    assert isinstance(agent, OpenLoopAgent if label != "ppo" else PolicyAgent)
    assert agent.env_id == SWIM["id"]
    assert agent.env_kwargs == {**SWIM["kwargs"], "water": {"model": "reactive"},  # recorded
                                "start_spread": FISH_START.as_dict()}
    reported = json.loads((folder / "result.json").read_text())["metrics"]
    result = evaluate(folder, seeds=[0, 1, 2, 3])  # the run's own 4 start states
    assert result["seeds"] == [0, 1, 2, 3]
    for key in ("eval/return", "eval/speed_bl_per_s"):
        assert result["metrics"][key] == pytest.approx(reported[key], rel=1e-6, abs=1e-9), key
    assert json.loads((folder / "eval.json").read_text())["metrics"] == result["metrics"]
    if label == "annealing-refined":
        artefacts = json.loads((folder / "artefacts.json").read_text())
        assert artefacts["budget"]["refine_env_steps"] == 1600


def test_a_run_folder_records_its_water_and_one_from_before_the_records_plays_resistive(
        tmp_path):
    """A new run's config.yaml names the water model it ran in and its start spread, so that
    it re-scores in them whatever the defaults become; a folder made before folders recorded
    them (its config names neither) ran in the resistive water from the point start, the
    defaults then, and loads, resumes and re-scores there."""
    import yaml

    folder = _run(tmp_path, "handmc")
    config = yaml.safe_load((folder / "config.yaml").read_text())
    assert config["env"]["kwargs"]["water"] == {"model": "reactive"}
    assert config["env"]["kwargs"]["start_spread"] == FISH_START.as_dict()
    reported = json.loads((folder / "result.json").read_text())["metrics"]["eval/return"]
    del config["env"]["kwargs"]["water"]  # as a folder of an earlier version has it
    del config["env"]["kwargs"]["start_spread"]
    (folder / "config.yaml").write_text(yaml.safe_dump(config))
    agent = load(folder)
    assert agent.env_kwargs["water"] == {"model": "resistive"}
    assert agent.env_kwargs["start_spread"] == POINT_START.as_dict()
    resistive = evaluate(folder, seeds=[0, 1, 2, 3])["metrics"]["eval/return"]
    assert resistive != pytest.approx(reported, rel=1e-3)  # played in the other water
    old = _run(tmp_path, "handmc-paper", env={**SWIM, "kwargs": {
        **SWIM["kwargs"], "water": {"model": "resistive"}, "start_spread": "point"}},
        learner="handmc", params={}, budget=40)
    assert json.loads((old / "result.json").read_text())["metrics"]["eval/return"] == (
        pytest.approx(resistive, rel=1e-9))


def test_macro_and_active_vision_runs_load_and_act(tmp_path):
    reach = {"id": "Animat/FishReach-v0", "kwargs": {"duration": 1.0}}
    repertoire = tmp_path / "fish.json"
    shutil.copyfile(ROOT / "repertoires" / "fish.json", repertoire)
    macro = _run(tmp_path, "macro", env=reach, params={
        "repertoire": str(repertoire), "slots": 2, "chains": 4, "max_duration": 1.0},
        budget=800, metric="eval/final_distance_bl")
    repertoire.write_text("overwritten by a later basic training")  # the run kept its copy
    reported = json.loads((macro / "result.json").read_text())["metrics"]
    assert evaluate(macro, seeds=[0, 1, 2, 3])["metrics"]["eval/return"] == pytest.approx(
        reported["eval/return"])
    status = json.loads((macro / "result.json").read_text())  # as if it had been killed
    (macro / "result.json").write_text(json.dumps({**status, "status": "failed"}))
    animat("run", "--resume", macro, "--quiet")  # from its own copy of the repertoire
    resumed = json.loads((macro / "result.json").read_text())
    assert resumed["status"] == "done" and resumed["metrics"] == reported
    pursuit = {"id": "Animat/FishPursuit-v0", "kwargs": {"duration": 1.0}}
    vision = _run(tmp_path, "vision", env=pursuit, learner="active_vision",
                  params={"episodes": 2}, budget=40, metric="eval/fovea_fraction")
    assert isinstance(load(vision), PolicyAgent)
    with pytest.raises(RunError, match="does not take physics_dt and frame_skip"):
        evaluate(vision, refine=2)
    reported = json.loads((vision / "result.json").read_text())["metrics"]
    result = evaluate(vision, seeds=[0, 1])  # the 2 episodes the run scored
    assert result["seeds"] == [0, 1]
    assert result["metrics"]["eval/fovea_fraction"] == pytest.approx(
        reported["eval/fovea_fraction"])


def test_eval_plays_start_states_the_run_never_saw_by_default(tmp_path):
    """By default ``animat eval`` scores a run on as many start states as it learned from,
    but drawn from seeds it never used (1,000,000 + its seed on), which differ."""
    folder = _run(tmp_path, "handmc")
    result = evaluate(folder)
    assert result["seeds"] == [1_000_000, 1_000_001, 1_000_002, 1_000_003]
    speeds = [row["speed_bl_per_s"] for row in result["episodes"]]
    assert np.ptp(speeds) > 0.01  # the starts differ: so do the figures
    own = evaluate(folder, seeds=[0, 1, 2, 3])["metrics"]["eval/speed_bl_per_s"]
    assert result["metrics"]["eval/speed_bl_per_s"] != own


def test_eval_prints_the_metric_and_films_every_episode(tmp_path):
    folder = _run(tmp_path, "handmc")
    out = animat("eval", folder, "--seeds", "5,6", "--video", tmp_path / "video")
    line = out.stdout.splitlines()[0]
    assert line.startswith("eval/speed_bl_per_s ") and "over 2 start states (seeds 5, 6" in line
    films = sorted((tmp_path / "video").glob("*.mp4"))
    assert len(films) == 2 and all(f.stat().st_size > 1000 for f in films)


def test_eval_at_a_finer_physics_step_plays_the_same_agent_beside_eval_json(tmp_path):
    folder = _run(tmp_path, "handmc")
    default = evaluate(folder)["metrics"]["eval/speed_bl_per_s"]
    out = animat("eval", folder, "--refine", "2")
    assert "at the physics step / 2" in out.stdout.splitlines()[0]
    assert "eval_step_over_2.json" in out.stdout
    finer = json.loads((folder / "eval_step_over_2.json").read_text())
    assert finer["physics_step_over"] == 2
    speed = finer["metrics"]["eval/speed_bl_per_s"]
    assert speed != default  # a finer solver ran
    assert speed == pytest.approx(default, rel=0.1, abs=1e-3)  # and agrees: converged
    assert json.loads((folder / "eval.json").read_text())["metrics"][
        "eval/speed_bl_per_s"] == default
    assert animat("eval", folder, "--refine", "0", check=False).returncode == 2


def test_eval_from_the_documented_start_plays_one_start_the_same_on_every_seed(tmp_path):
    """``--point-start``: the agent from the task's placement alone (no spread, no reset
    noise), one episode by default, beside eval.json; every seed plays the same start."""
    folder = _run(tmp_path, "handmc")
    spread = evaluate(folder, episodes=2)["metrics"]["eval/speed_bl_per_s"]
    out = animat("eval", folder, "--point-start")
    assert "eval_point_start.json" in out.stdout and "over 1 start states" in out.stdout
    point = json.loads((folder / "eval_point_start.json").read_text())
    assert point["start"] == "point" and len(point["episodes"]) == 1
    again = evaluate(folder, seeds=[5, 6], point_start=True)["episodes"]
    figures = [{k: v for k, v in e.items() if k != "seed"} for e in again]
    assert figures[0] == figures[1] == {k: v for k, v in point["episodes"][0].items()
                                        if k != "seed"}
    assert point["metrics"]["eval/speed_bl_per_s"] != spread
    assert json.loads((folder / "eval.json").read_text())["metrics"][
        "eval/speed_bl_per_s"] == spread  # eval.json is left as it was


def test_a_repertoire_run_loads_as_one_agent_per_skill(tmp_path):
    regimen = [{"name": "swim_slow", "env_id": "Animat/FishSwim-v0",
                "env_kwargs": {"duration": 0.5}, "params": {"nodes": 4, "period": 0.5}},
               {"name": "turn_left", "env_id": "Animat/FishTurn-v0",
                "env_kwargs": {"duration": 0.5, "angle_deg": 30.0},
                "params": {"nodes": 4, "period": None}}]
    folder = _run(tmp_path, "basic", learner="basic_training", params={
        "regimen": regimen, "annealing": {"chains": 4}, "output": str(tmp_path / "rep.json")},
        budget=640)
    (tmp_path / "rep.json").unlink()  # the run folder keeps its own copy
    skills = load(folder)
    assert isinstance(skills, SkillSet) and sorted(skills.agents) == ["swim_slow", "turn_left"]
    assert skills.agents["turn_left"].env_id == "Animat/FishTurn-v0"
    result = evaluate(folder, episodes=1)
    assert set(result["metrics"]) == {"swim_slow", "turn_left"}
    assert all(np.isfinite(m["eval/return"]) for m in result["metrics"].values())
    rows = {r["skill"]: r for r in repertoire_rows(folder)}  # the README's table of it
    assert rows["turn_left"]["figure"] == "eval/final_heading_error_deg"
    assert rows["swim_slow"]["unseen"] == result["metrics"]["swim_slow"]["eval/speed_bl_per_s"]
    assert rows["swim_slow"]["unseen_starts"] == 1
    table = repertoire_markdown(list(rows.values())).splitlines()
    assert len(table) == 4 and table[2].startswith("| swim_slow | ") and "over 1 |  |" in table[2]
    error = result["metrics"]["turn_left"]["eval/final_heading_error_deg"]
    assert rows["turn_left"]["unseen_within"] == int(error <= 10.0)  # one start: 0 or 1 of 1
    assert table[3].endswith(f"| {int(error <= 10.0)}/1 |")


def test_only_a_finished_run_loads(tmp_path):
    folder = _run(tmp_path, "handmc")
    status = json.loads((folder / "result.json").read_text())
    (folder / "result.json").write_text(json.dumps({**status, "status": "failed"}))
    with pytest.raises(RunError, match="the run is failed; only a finished run"):
        load(folder)
    assert animat("eval", folder, check=False).returncode == 2


def test_a_shipped_result_is_re_scored_against_what_it_quotes_and_never_written(
        tmp_path, monkeypatch):
    """A run folder under the repository's results/ is a quoted result: ``animat eval``
    compares its score with the shipped eval.json and writes nothing into it."""
    from animat.experiments.launch import shipped

    monkeypatch.setattr(shipped, "RESULTS", tmp_path)
    folder = _run(tmp_path, "handmc")
    first = evaluate(folder)
    assert "left as it is" in first["shipped"] and not (folder / "eval.json").exists()
    quoted = {k: first[k] for k in ("seeds", "metric", "episodes", "metrics")}
    (folder / "eval.json").write_text(json.dumps(quoted))
    assert evaluate(folder)["shipped"].startswith("the same as the shipped")
    quoted["metrics"]["eval/return"] += 1e-3
    (folder / "eval.json").write_text(json.dumps(quoted))
    before = (folder / "eval.json").read_bytes()
    line = evaluate(folder)["shipped"]
    assert line.startswith("DIFFERENT from the shipped") and "eval/return by" in line
    assert (folder / "eval.json").read_bytes() == before


def test_the_rescore_table_says_which_shipped_folder_moved_and_by_how_much(
        tmp_path, monkeypatch, capsys):
    """``rescore_table``: a row a shipped folder, the one whose eval.json no longer matches
    named with its figure and move; exit 1 then, 0 when all match; nothing written; a folder
    outside results/ refused."""
    from animat.experiments.figures import rescore_table
    from animat.experiments.launch import shipped

    monkeypatch.setattr(shipped, "RESULTS", tmp_path)
    monkeypatch.setattr(rescore_table, "RESULTS", tmp_path)
    folders = [_run(tmp_path, "handmc"), shutil.copytree(tmp_path / "handmc", tmp_path / "b")]
    for folder in folders:
        quoted = evaluate(folder, episodes=2)
        (folder / "eval.json").write_text(json.dumps(
            {k: quoted[k] for k in ("seeds", "metric", "episodes", "metrics")}))
    assert rescore_table.main([]) == 0
    moved = json.loads((folders[1] / "eval.json").read_text())
    moved["metrics"]["eval/speed_bl_per_s"] *= 1.01
    (folders[1] / "eval.json").write_text(json.dumps(moved))
    before = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()}
    assert rescore_table.main([]) == 1
    rows = capsys.readouterr().out.splitlines()
    assert any(r.startswith("| handmc | yes |") for r in rows)
    assert any(r.startswith("| b | NO | eval/speed_bl_per_s | 0.0099 |") for r in rows)
    assert "1 of 2 folders re-score" in rows[-1]
    assert {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()} == before
    assert rescore_table.main([str(tmp_path.parent)]) == 2


def test_largest_move_names_the_figure_and_weighs_it_by_its_spread():
    shipped = {"turn": {"eval/a": 2.0, "eval/a_std": 0.5, "eval/b": 10.0, "eval/b_std": 4.0},
               "swim": {"eval/c": 1.0, "eval/c_std": 0.0}}
    scored = {"turn": {"eval/a": 2.1, "eval/a_std": 0.5, "eval/b": 10.0, "eval/b_std": 9.0},
              "swim": {"eval/c": 1.0, "eval/c_std": 0.0}}
    name, relative, in_spread = largest_move(shipped, scored)
    assert name == "turn/eval/a" and relative == pytest.approx(0.05) and in_spread == (
        pytest.approx(0.2))
    scored["swim"]["eval/c"] = 1.5  # no spread to weigh it by
    assert largest_move(shipped, scored) == ("swim/eval/c", 0.5, np.inf)
    assert largest_move(shipped, shipped) == ("", 0.0, 0.0)


def test_a_shipped_comparison_says_when_only_spreads_or_the_figures_themselves_differ(tmp_path):
    path = tmp_path / "eval.json"
    metrics = {"eval/a": 1.0, "eval/a_std": 0.5}
    path.write_text(json.dumps({"seeds": [1], "metrics": metrics}))
    assert "the same as" in shipped_comparison(path, {"seeds": [1], "metrics": metrics})
    spread = {"eval/a": 1.0, "eval/a_std": 0.6}
    assert shipped_comparison(path, {"seeds": [1], "metrics": spread}).endswith(
        "(only the spreads over the starts moved)")
    other = {"eval/b": 1.0, "eval/b_std": 0.5}
    assert shipped_comparison(path, {"seeds": [1], "metrics": other}).endswith("(other figures)")


def test_a_figure_a_task_added_since_is_named_and_the_shipped_ones_are_compared(tmp_path):
    """A re-score with a figure the shipped file predates (a metric added to the task since)
    is the same on the figures the file quotes; a move of one of those is still a move."""
    path = tmp_path / "eval.json"
    path.write_text(json.dumps({"seeds": [1], "metrics": {"skill": {"eval/a": 1.0}}}))
    added = {"skill": {"eval/a": 1.0, "eval/held": 0.0}}
    assert shipped_comparison(path, {"seeds": [1], "metrics": added}).endswith(
        "(on its figures; added since: skill/eval/held)")
    moved = {"skill": {"eval/a": 2.0, "eval/held": 0.0}}
    assert "the largest move: skill/eval/a" in shipped_comparison(
        path, {"seeds": [1], "metrics": moved})


def test_the_unseen_table_groups_runs_by_learner_with_own_and_unseen_figures(tmp_path, capsys):
    """``unseen_table``: one row per learner over its seeds, the own-start figure from
    result.json and the unseen one from eval.json (a run without one is named and left out of
    that column)."""
    from animat.experiments.figures.unseen_table import main, run_rows

    first = _run(tmp_path, "handmc")
    second = _run(tmp_path, "cmaes")
    evaluate(first, episodes=2)
    rows = run_rows([first, second], "eval/speed_bl_per_s")
    unseen = json.loads((first / "eval.json").read_text())["metrics"]["eval/speed_bl_per_s"]
    own = json.loads((first / "result.json").read_text())["metrics"]["eval/speed_bl_per_s"]
    assert rows[0]["learner"] == "handmc" and rows[0]["unseen"] == unseen
    assert rows[0]["own"] == own and rows[1]["unseen"] is None
    assert main([str(first), str(second), "--metric", "eval/speed_bl_per_s"]) == 0
    out = capsys.readouterr()
    table = out.out.splitlines()
    assert table[2].startswith("| cmaes | 0 | ") and "| n/a | n/a |" in table[2]
    assert table[3].startswith(f"| handmc | 0 | {own:.2f} ± 0.00")
    assert f"| {unseen:.2f} ± 0.00" in table[3]
    assert "has no eval.json" in out.err


def test_the_unseen_table_counts_each_runs_unseen_starts_that_meet_a_criterion(tmp_path, capsys):
    """``unseen_table --at-least X`` / ``--at-most X``: each run's number of unseen starts (of
    eval.json's episodes) whose figure meets the bound, in a column of its own."""
    from animat.experiments.figures.unseen_table import main, run_rows

    run = _run(tmp_path, "handmc")
    evaluate(run, episodes=3)
    speeds = [e["speed_bl_per_s"] for e in json.loads((run / "eval.json").read_text())["episodes"]]
    middle = sorted(speeds)[1]
    rows = run_rows([run], "eval/speed_bl_per_s", lambda v: v >= middle)
    assert (rows[0]["met"], rows[0]["starts"]) == (2, 3)
    assert main([str(run), "--metric", "eval/speed_bl_per_s", "--at-most", str(middle)]) == 0
    table = capsys.readouterr().out.splitlines()
    assert f"unseen starts ≤ {middle:g}, each run" in table[0] and "| 2/3 |" in table[2]


def test_the_unseen_table_shows_the_documented_start_where_a_run_was_played_from_it(
        tmp_path, capsys):
    """A run with eval_point_start.json adds a column of its figure from the documented start;
    a table of runs without one has no such column."""
    from animat.experiments.figures.unseen_table import main, run_rows

    run = _run(tmp_path, "handmc")
    evaluate(run, episodes=2)
    assert main([str(run), "--metric", "eval/speed_bl_per_s"]) == 0
    assert "documented start" not in capsys.readouterr().out
    point = evaluate(run, point_start=True)["metrics"]["eval/speed_bl_per_s"]
    assert run_rows([run], "eval/speed_bl_per_s")[0]["documented"] == point
    assert main([str(run), "--metric", "eval/speed_bl_per_s", "--at-least", "0"]) == 0
    table = capsys.readouterr().out.splitlines()
    assert "| eval/speed_bl_per_s, documented start |" in table[0]
    assert table[1].count("|") == table[0].count("|") == table[2].count("|")
    assert table[2].startswith(f"| handmc | 0 | {point:.2f} ± 0.00") and "| 2/2 |" in table[2]


def test_the_pursuit_table_sets_each_policy_between_its_blind_and_oracle_baselines(
        tmp_path, capsys):
    """``pursuit_table``: the unseen fovea fraction of each run of a benchmark variant, and the
    same normalised so that the variant's blind run is 0 and its oracle 1 (the oracle's
    privileged entry and the glances are not part of the variant)."""
    from animat.experiments.figures.pursuit_table import main, normalised, pursuit_rows

    pursuit = {"id": "Animat/FishPursuit-v0", "kwargs": {"duration": 1.0}}
    folders = {}
    for label, params, kwargs in [("vision", {}, {}), ("blind", {"blind": True}, {}),
                                  ("oracle", {"oracle": True}, {"oracle": True})]:
        env = {**pursuit, "kwargs": {**pursuit["kwargs"], **kwargs}}
        folders[label] = _run(tmp_path, label, env=env, learner="active_vision",
                              params={"episodes": 1, **params}, budget=20,
                              metric="eval/fovea_fraction")
        evaluate(folders[label], episodes=2)
    rows = {r["role"]: r for r in pursuit_rows(list(folders.values()))}
    assert len({r["variant"] for r in rows.values()}) == 1
    # what an agent observes (its sensors, its frames) is not part of the variant either
    observer = tmp_path / "observer"
    shutil.copytree(folders["vision"], observer)
    config = yaml.safe_load((observer / "config.yaml").read_text())
    config["env"]["kwargs"].update(frames=3, sensors=[{"name": "pixels", "size": 32}, "gaze"])
    (observer / "config.yaml").write_text(yaml.safe_dump(config))
    both = pursuit_rows([*folders.values(), observer])
    assert {r["variant"] for r in both} == {rows["policy"]["variant"]}
    # ... but its row says what it observes
    assert {r["label"] for r in both} == {"active_vision", "active_vision (pixels, gaze)"}
    shutil.rmtree(observer)
    share = {role: r["metrics"]["eval/fovea_fraction"] for role, r in rows.items()}
    assert main([str(tmp_path)]) == 0
    out = capsys.readouterr().out
    expected = normalised(share["policy"], share["blind"], share["oracle"])
    assert f"| active_vision | 1 | {share['policy']:.2f} ± " in out
    assert expected == "n/a" or f"| {expected} |" in out
    assert normalised(0.5, 0.1, 0.9) == "0.50" and normalised(0.5, None, 0.9) == "n/a"
    # a config run on several seeds: each row names its seed
    second = tmp_path / "vision_seed3"
    shutil.copytree(folders["vision"], second)
    config = yaml.safe_load((second / "config.yaml").read_text())
    (second / "config.yaml").write_text(yaml.safe_dump({**config, "seed": 3}))
    assert main([str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "| active_vision, seed 0 | 1 |" in out and "| active_vision, seed 3 | 1 |" in out
    assert out.count(", seed ") == 2  # the baselines, one run each, are named alone
