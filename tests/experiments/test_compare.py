"""``animat compare`` cannot mislead: runs of different settings are refused, naming them; the
metric is the configs' own by default; the interquartile mean comes with its stratified-
bootstrap interval; a report has a performance profile, each learner in one colour."""

import json

import numpy as np

from animat.experiments.compare import setting_of
from animat.experiments.figures.curves import RunCurves, learner_colours
from animat.experiments.figures.statistics import iqm, iqm_interval
from tests.support.cli import TINY, animat, write_config


def test_runs_of_two_settings_are_refused_in_one_line_naming_both(tmp_path):
    config = write_config(tmp_path / "tiny.yaml", TINY)
    animat("run", config, "--out", tmp_path / "runs" / "reactive", "--quiet")
    animat("run", config, "--out", tmp_path / "runs" / "resistive", "--quiet",
           "--set", "env.kwargs.water={model: resistive}")
    refused = animat("compare", tmp_path / "runs", check=False)
    assert refused.returncode == 2 and len(refused.stderr.strip().splitlines()) == 1
    assert "Animat/FishSwim-v0, reactive water: 1 runs" in refused.stderr
    assert "Animat/FishSwim-v0, resistive water: 1 runs" in refused.stderr
    alone = animat("compare", tmp_path / "runs" / "reactive").stdout  # one setting: compared
    assert alone.startswith("Runs of Animat/FishSwim-v0, reactive water; metric "
                            "`eval/speed_bl_per_s`")  # the config's metric, not eval/return


def test_a_setting_names_the_env_its_water_and_a_non_default_integrator():
    assert setting_of("Animat/FishTurn-v0", {}) == "Animat/FishTurn-v0, resistive water"
    assert setting_of("Animat/FishSwim-v0", {"water": {"model": "reactive"},
                                             "integrator": "implicit"}) == (
        "Animat/FishSwim-v0, reactive water, implicit")


def test_the_interquartile_mean_and_its_interval():
    assert iqm(np.array([1.0, 2.0, 3.0])) == 2.0  # fewer than four: every run
    assert iqm(np.array([100.0, 1.0, 3.0, 2.0, 4.0])) == 3.0  # one cut from each end
    assert iqm(np.array([5.0, 1.0, 2.0, 3.0, 4.0, 6.0, 7.0, 8.0])) == 4.5
    value, low, high = iqm_interval(np.array([0.5, 0.9, 1.0, 1.1, 1.2, 3.0]))
    assert low <= value <= high and low < high
    assert iqm_interval(np.full(4, 2.0)) == (2.0, 2.0, 2.0) and iqm_interval(np.array([])) is None


def test_a_report_has_the_iqm_and_a_performance_profile(tmp_path):
    config = write_config(tmp_path / "tiny.yaml", TINY)
    for seed in (0, 1):
        animat("run", config, "--set", f"seed={seed}", "--quiet",
               "--out", tmp_path / "runs" / f"s{seed}")
    report = tmp_path / "report.md"
    animat("compare", tmp_path / "runs", "-o", report)
    text = report.read_text()
    assert "IQM of result" in text and "stratified-bootstrap interval" in text
    assert "![performance profile](report_profile.png)" in text
    profile = tmp_path / "report_profile.png"
    assert profile.exists() and profile.stat().st_size > 5000
    assert json.loads(report.with_suffix(".json").read_text())["rows"][0]["result_iqm"]


def test_each_learner_keeps_one_colour_whatever_the_runs_order():
    def run(name):
        return RunCurves(None, name, "Animat/FishSwim-v0", 0, {}, {})
    one = learner_colours([run("ppo"), run("annealing"), run("cmaes")])
    two = learner_colours([run("cmaes"), run("ppo"), run("annealing"), run("ppo")])
    assert one == two and len(set(one.values())) == 3
