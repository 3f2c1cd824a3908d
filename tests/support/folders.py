"""Run folders as the launcher leaves them: finished runs of the tiny config, and a run's
``result.json`` rewritten as a run would leave it (failed, running, on another host)."""

import json

from tests.support.cli import TINY, animat, write_config


def finished(tmp_path, *names: str) -> list:
    """Run folders ``tmp_path/runs/<name>`` of the tiny config, each finished."""
    config = write_config(tmp_path / "tiny.yaml", TINY)
    folders = [tmp_path / "runs" / name for name in names]
    for folder in folders:
        animat("run", config, "--out", folder, "--quiet")
    return folders


def set_status(folder, **fields) -> None:
    """Rewrite the run's result.json with ``fields`` changed (a run as it would be left)."""
    status = json.loads((folder / "result.json").read_text())
    (folder / "result.json").write_text(json.dumps({**status, **fields}))
