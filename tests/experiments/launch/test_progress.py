"""A run's progress: log lines off a terminal (a tenth of the budget at a time, and when it is
done), a bar that ends at the env steps the run made, and a notice before the kernels compile."""

import json
import re

import yaml

from animat.experiments.launch import progress
from animat.experiments.launch.progress import ProgressLog, ProgressSink
from tests.support.cli import TINY, animat


def test_off_a_terminal_a_run_logs_each_tenth_of_its_budget_and_its_end(tmp_path):
    config = tmp_path / "tiny.yaml"
    config.write_text(yaml.safe_dump(TINY))
    out = animat("run", config, "--out", tmp_path / "run").stdout
    lines = [line for line in out.splitlines() if line.startswith("animat: ")]
    shares = [int(m.group(1)) for line in lines if (m := re.match(r"animat: (\d+)%", line))]
    assert shares == sorted(shares) and len(shares) == len(set(shares)) and shares[-1] >= 90
    done = json.loads(out.strip().splitlines()[-1])["env_steps"]
    assert lines[-1].startswith(f"animat: done: {done:,} of 3,200 env steps")
    assert all("env steps/s" in line for line in lines)


def test_a_log_line_for_every_tenth_passed_however_the_steps_fall(capsys):
    log = ProgressLog(1000, "eval/return", label="seed_3")
    for step in (50, 99, 100, 350, 351, 999, 1000):
        log.scalar("eval/return", step / 100, step)
    log.finish(1000)
    lines = capsys.readouterr().out.splitlines()
    assert [line.split(":")[2].strip() for line in lines] == ["10%", "35%", "99%", "100%",
                                                               "done"]
    assert lines[0].startswith("animat: seed_3: 10%: 100 of 1,000 env steps")
    assert "best eval/return 10" in lines[-1]


def test_the_bar_ends_full_at_the_steps_the_run_made():
    bar = ProgressSink(100_000, "eval/return")
    bar.scalar("eval/return", 1.0, 76_400)
    bar.finish(76_800)  # the last scores logged, then the run's own total
    task = bar._progress.tasks[0]
    bar.close()
    assert task.total == task.completed == 76_800


def test_a_notice_before_the_kernels_compile_and_none_after(monkeypatch, capsys):
    assert progress.kernels_compiled()  # the suite has run the kernels by now
    progress.compile_notice()
    assert capsys.readouterr().err == ""
    monkeypatch.setattr(progress, "kernels_compiled", lambda: False)
    progress.compile_notice()
    err = capsys.readouterr().err
    assert err.startswith("animat: compiling the physics kernels") and err.count("\n") == 1
