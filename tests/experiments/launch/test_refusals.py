"""The launcher's refusals: every value a run reads is checked before its run folder exists,
and a refusal is one line on stderr naming the file and the field, with exit status 2.

Each case is a config file's text (or the file itself: a device, a FIFO, a file too large),
the ``--set`` overrides given with it, and what the one line must say; the run's ``--out``
folder must not exist afterwards."""

from __future__ import annotations

import os
import threading
import time
from pathlib import Path

import pytest
import yaml

from animat.experiments import cli
from animat.experiments.launch.config import load_config, load_run_config
from animat.experiments.launch.shipped import CONFIGS, shipped_configs

ROOT = Path(__file__).resolve().parents[3]
TINY = {"env": {"id": "Animat/FishSwim-v0", "kwargs": {"duration": 0.5}},
        "learner": {"name": "annealing", "params": {"chains": 8, "nodes": 4, "period": 0.5}},
        "budget": {"env_steps": 3200}, "seed": 0, "eval": {"metric": "eval/speed_bl_per_s"}}
PPO = {**TINY, "learner": {"name": "ppo", "params": {"n_envs": 2, "n_steps": 16,
                                                     "batch_size": 32}}}
CMAES = {**TINY, "learner": {"name": "cmaes", "params": {"popsize": 8, "nodes": 4,
                                                         "period": 0.5}}}


def _text(data: dict, **changes) -> str:
    """``data`` as YAML, with ``changes`` (a dotted field path, ``__`` for ``.``: its value)
    made."""
    data = yaml.safe_load(yaml.safe_dump(data))
    for path, value in changes.items():
        *parents, last = path.split("__")
        node = data
        for key in parents:
            node = node[key]
        node[last] = value
    return yaml.safe_dump(data, sort_keys=False)


DIGITS = "1" * 5000
# case: (config text, overrides, what the one line says after the file's name)
CASES = {
    "ppo_seed_1e26": (_text(PPO), [f"seed={10**26}"], "seed: "),
    "seed_2_to_the_32": (_text(TINY, seed=2**32), [], "seed: "),
    "step_size_inf": (_text(TINY, learner__params__step_size=float("inf")), [],
        "learner.params: learner 'annealing': step_size must be a "
        "finite number"),
    "step_size_nan": (_text(TINY, learner__params__step_size=float("nan")), [],
        "learner.params: learner 'annealing': step_size must be a "
        "finite number"),
    "refine_step_size_inf": (_text(TINY, learner__params__refine={
        "share": 0.25, "step_size": float("inf")}), [],
        "learner.params: learner 'annealing': refine.step_size must be a finite number"),
    "cmaes_sigma0_inf": (_text(CMAES, learner__params__sigma0=float("inf")), [],
        "learner.params: learner 'cmaes': sigma0 must be a finite number"),
    "cmaes_tolfun_nan": (_text(CMAES, learner__params__tolfun=float("nan")), [],
        "learner.params: learner 'cmaes': tolfun must be a finite number"),
    "ppo_on_swimmer": (_text(PPO, env={"id": "Swimmer-v5"}), [],
        "env.id: learner 'ppo' drives"),
    "annealing_on_swimmer": (_text(TINY), ["env.id=Swimmer-v5", "env.kwargs={}"],
        "env.id: learner 'annealing' drives"),
    "annealing_on_pursuit": (_text(TINY, env={"id": "Animat/FishPursuit-v0"}), [],
        "env.id: learner 'annealing' drives"),
    "regimen_skill_on_swimmer": (_text(TINY, learner={"name": "basic_training", "params": {
        "regimen": [{"name": "swim", "env_id": "Swimmer-v5"}]}}), [],
        "learner.params: regimen skill 'swim': learner 'annealing' drives"),
    "threshold_nan": (_text(TINY, eval={"metric": "eval/return", "threshold": float("nan")}),
        [], "eval.threshold: "),
    "threshold_inf": (_text(TINY), ["eval.threshold=-.inf"], "eval.threshold: "),
    "metric_bogus": (_text(TINY, eval={"metric": "eval/bogus"}), [],
        "eval.metric: eval/bogus is not a metric Animat/FishSwim-v0 reports"),
    "metric_of_another_task": (_text(TINY), ["eval.metric=eval/reached"],
        "eval.metric: eval/reached is not a metric"),
    "duplicate_key": (_text(TINY) + "seed: 3\n", [], "seed: duplicate key 'seed'"),
    "duplicate_nested_key": (_text(TINY).replace("chains: 8", "chains: 8\n    chains: 9"), [],
        "learner.params.chains: duplicate key 'chains'"),
    "duplicate_key_in_set": (_text(TINY), ["learner.params={chains: 8, chains: 9}"],
        "learner.params.chains: duplicate key 'chains'"),
    "budget_1e30": (_text(TINY), [f"budget.env_steps={10**30}"], "budget.env_steps: "),
    "budget_10_to_the_16": (_text(TINY, budget={"env_steps": 10**16}), [], "budget.env_steps: "),
    "params_a_list": (_text(TINY, learner={"name": "annealing", "params": [1]}), [],
        "learner.params: "),
    "params_a_list_in_set": (_text(TINY), ["learner.params=[1]"], "learner.params: "),
    "seed_5000_digits": (_text(TINY).replace("seed: 0", f"seed: {DIGITS}"), [], "seed: "),
    "seed_5000_digits_in_set": (_text(TINY), [f"seed={DIGITS}"], "seed: "),
    "param_5000_digits": (_text(TINY).replace("chains: 8", f"chains: {DIGITS}"), [],
        "learner.params.chains: "),
    "impossible_date": (_text(TINY).replace("seed: 0", "seed: 2001-13-45"), [],
        "not valid YAML: month must be in 1..12"),
    "set_unclosed": (_text(TINY), ["seed=[unclosed"], "seed: cannot read value"),
    "set_nested_deep": (_text(TINY), ["seed=" + "[" * 20_000], "seed: "),
    "nested_20000_lists": ("[" * 20_000, [], "nested deeper than"),
    "nested_20000_maps": ("{a: " * 20_000, [], "nested deeper than"),
    "config_2_mib": (_text(TINY) + ("# padding\n" * 210_000), [], "holds 2,"),
}


def _refused(capsys, config: str | Path, overrides: list[str], out: Path) -> str:
    """``animat run CONFIG --set ... --out OUT``: its one stderr line, having checked the exit
    status (2), that there is one line, and that OUT was never made."""
    args = ["run", str(config), *(a for o in overrides for a in ("--set", o)),
            "--out", str(out), "--quiet"]
    code = cli.main(args)
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1, err
    assert lines[0].startswith("animat: error: "), lines[0]
    assert not out.exists()
    return lines[0]


@pytest.mark.parametrize("text, overrides, says", CASES.values(), ids=CASES.keys())
def test_a_bad_value_is_refused_in_one_line_naming_file_and_field_before_the_folder(
        tmp_path, capsys, text, overrides, says):
    config = tmp_path / "bad.yaml"
    config.write_text(text)
    start = time.perf_counter()
    line = _refused(capsys, config, overrides, tmp_path / "run")
    assert f"{config}: {says}" in line, line
    assert time.perf_counter() - start < 10


def test_nesting_is_refused_within_a_second(tmp_path, capsys):
    config = tmp_path / "deep.yaml"
    config.write_text("[" * 20_000)
    _refused(capsys, config, [], tmp_path / "warm")  # imports made
    start = time.perf_counter()
    _refused(capsys, config, [], tmp_path / "run")
    assert time.perf_counter() - start < 1


def test_a_device_is_refused_as_a_config(tmp_path, capsys):
    line = _refused(capsys, "/dev/zero", [], tmp_path / "run")
    assert "/dev/zero: is a character device, not a regular file" in line


def test_a_fifo_is_refused_as_a_config_without_waiting_for_a_writer(tmp_path, capsys):
    fifo = tmp_path / "config.yaml"
    os.mkfifo(fifo)

    def unblock():  # were the FIFO opened to read, it would wait for this writer
        time.sleep(10)
        try:
            os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))
        except OSError:
            pass

    threading.Thread(target=unblock, daemon=True).start()
    start = time.perf_counter()
    line = _refused(capsys, fifo, [], tmp_path / "run")
    assert time.perf_counter() - start < 5 and f"{fifo}: is a FIFO" in line


def test_a_config_named_through_a_link_is_read(tmp_path, capsys):
    real = tmp_path / "real.yaml"
    real.write_text(_text(TINY, eval={"metric": "eval/bogus"}))
    (tmp_path / "link.yaml").symlink_to(real)
    line = _refused(capsys, tmp_path / "link.yaml", [], tmp_path / "run")
    assert f"{tmp_path / 'link.yaml'}: eval.metric: eval/bogus" in line


def test_a_run_folders_config_that_is_a_link_is_refused(tmp_path, capsys):
    outside = tmp_path / "outside.yaml"
    outside.write_text(_text(TINY))
    folder = tmp_path / "run"
    folder.mkdir()
    (folder / "config.yaml").symlink_to(outside)
    with pytest.raises(ValueError, match="config.yaml: is a symbolic link"):
        load_run_config(folder)
    code = cli.main(["run", "--resume", str(folder), "--quiet"])
    lines = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and "config.yaml: is a symbolic link" in lines[0]
    assert sorted(p.name for p in folder.iterdir()) == ["config.yaml"]


def test_every_shipped_config_and_shipped_run_folder_still_validates():
    """Every shipped config builds (its metric one its env reports, its env one its learner
    drives); so does every shipped result's config.yaml, read as a run folder's."""
    from animat.learners.registry import LEARNERS
    from animat.learners.validation import DRIVES

    assert set(DRIVES) == set(LEARNERS)  # every learner says what it drives
    assert shipped_configs()
    for name in shipped_configs():
        load_config(CONFIGS / f"{name}.yaml", build=True)
    folders = sorted(p.parent for p in (ROOT / "results").rglob("config.yaml"))
    assert folders
    for folder in folders:
        load_run_config(folder, build=True)
