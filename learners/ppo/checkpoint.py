"""PPO checkpoints as data, each written whole before it becomes the one a resume reads.

A checkpoint is a folder ``checkpoints/ppo/save-<k>/``:

- ``policy.pt``: the policy's ``state_dict`` (tensors), ``optimizer.pt``: its optimiser's;
  both read back with ``torch.load(weights_only=True)``, which refuses anything but tensors
  and plain containers, so a planted pickle cannot run code;
- ``normalize.npz``: the observation and return statistics of ``VecNormalize`` (read with
  ``allow_pickle=False``), when the run normalises;
- ``state.json``: ``num_timesteps``, SB3's update count, the learner's wall time and metrics;
- ``resume.json`` (:mod:`animat.learners.storage.checkpoint_data`'s JSON, arrays bit for bit): what
  continues the run exactly besides the weights: the random generators (torch's, NumPy's
  global one and Python's, which SB3 seeds and draws from), the envs' state (their
  ``get_state()``: :mod:`animat.learners.ppo.vec_envs`), the observation and episode starts
  SB3 steps on from, and the SB3 logger's records not yet written (the last update's
  ``train/*``). A checkpoint is taken between rollouts, so a resumed run collects and trains
  on exactly what the whole run would, and logs the same numbers.

It is written as ``save-<k>.partial/`` and made a checkpoint by one rename; only then does
``checkpoints/ppo/latest.json`` (written atomically) point at it, and only then is the previous
one removed: a kill at any moment leaves the last complete checkpoint readable. The model and
its ``VecNormalize`` are rebuilt from the run's config (the same code that makes a fresh one),
then given the saved numbers.
"""

from __future__ import annotations

import json
import os
import pickle
import random
import re
import shutil
import zipfile
from pathlib import Path

import numpy as np

from ..storage import checkpoint_data
from ..storage.files import (
    CorruptFile,
    UnsafeFile,
    atomic_write,
    is_regular,
    make_dirs,
    open_stored_zip,
    read_json,
)

FOLDER = "ppo"
LATEST = "latest.json"
RESUME = "resume.json"
SAVE_NAME = re.compile(r"save-(\d{6})(\.partial)?")  # a checkpoint's folder, or one being written
ANSI = re.compile(r"\x1b\[[0-9;]*m")  # colour codes in torch's messages
RESUME_FORMAT = "artificial-animals PPO resume state 1"


def _running(venv) -> list[tuple[str, object]]:
    """VecNormalize's RunningMeanStd objects by name: ``obs:`` (or ``obs:<key>`` for each key
    of a Dict observation) and ``ret``."""
    rms = venv.obs_rms
    named = dict(rms.items()) if isinstance(rms, dict) else {"": rms}
    return [*((f"obs:{k}", v) for k, v in named.items()), ("ret", venv.ret_rms)]


def _stats(venv) -> dict[str, np.ndarray]:
    """VecNormalize's running statistics as named arrays (empty without normalisation)."""
    if not hasattr(venv, "obs_rms"):
        return {}
    out = {}
    for key, stats in _running(venv):
        out[f"{key}:mean"], out[f"{key}:var"] = np.asarray(stats.mean), np.asarray(stats.var)
        out[f"{key}:count"] = np.asarray(stats.count)
    out["returns"] = np.asarray(venv.returns)
    return out


def _restore_stats(venv, path: Path) -> None:
    """Set VecNormalize's statistics from ``normalize.npz``."""
    try:
        with open_stored_zip(path, "arrays") as file, np.load(file, allow_pickle=False) as saved:
            data = {k: saved[k] for k in saved.files}
        for key, stats in _running(venv):
            stats.mean, stats.var = data[f"{key}:mean"], data[f"{key}:var"]
            stats.count = float(data[f"{key}:count"])
        venv.returns = data["returns"]
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile) as error:
        if isinstance(error, UnsafeFile | FileNotFoundError):
            raise
        raise CorruptFile(path, f"not the run's normalisation statistics ({error})") from None


def save(checkpoint_dir: Path, model, venv, state: dict) -> Path:
    """Write a new checkpoint of ``model`` (and ``venv``'s statistics) and make it the latest;
    returns its folder."""
    import torch

    root = make_dirs(Path(checkpoint_dir) / FOLDER)
    index = 1 + max((int(match[1]) for p in root.glob("save-*")
                     if (match := SAVE_NAME.fullmatch(p.name))), default=0)
    final, partial = root / f"save-{index:06d}", root / f"save-{index:06d}.partial"
    partial.mkdir()
    torch.save(model.policy.state_dict(), partial / "policy.pt")
    torch.save(model.policy.optimizer.state_dict(), partial / "optimizer.pt")
    stats = _stats(venv)
    if stats:
        np.savez(partial / "normalize.npz", **stats)
    (partial / "state.json").write_text(json.dumps(
        {**state, "num_timesteps": int(model.num_timesteps), "n_updates": int(model._n_updates)}))
    checkpoint_data.save(partial / RESUME, _progress(model, venv), RESUME_FORMAT)
    for path in partial.iterdir():  # on disk before the rename makes it a checkpoint
        with path.open("rb") as file:
            os.fsync(file.fileno())
    os.rename(partial, final)
    _fsync_folder(root)
    atomic_write(root / LATEST, lambda file: json.dump({"folder": final.name}, file))
    _fsync_folder(root)
    for old in root.glob("save-*"):
        if old != final:
            shutil.rmtree(old, ignore_errors=True)
    return final


def _fsync_folder(folder: Path) -> None:
    """Put a folder's entries (a rename into it) on disk."""
    handle = os.open(folder, os.O_RDONLY)
    try:
        os.fsync(handle)
    finally:
        os.close(handle)


def _progress(model, venv) -> dict:
    """What continues the run exactly besides the weights (``resume.json``; see the module's
    docstring)."""
    import torch

    log = model.logger
    return {"rng": {"torch": torch.get_rng_state().numpy(),
                    "numpy": np.random.get_state(legacy=False), "python": random.getstate()},
            "env": venv.unwrapped.get_state(),
            "last_obs": _obs_laid_out(model._last_obs),
            "last_episode_starts": model._last_episode_starts,
            "last_original_obs": model._last_original_obs,
            "pending_log": {"values": dict(log.name_to_value), "counts": dict(log.name_to_count),
                            "excluded": dict(log.name_to_excluded)}}


def _obs_laid_out(obs) -> dict:
    """A batch's observation, each entry (``""`` for a Box's) in its memory order."""
    named = obs if isinstance(obs, dict) else {"": obs}
    return {key: _in_memory_order(value) for key, value in named.items()}


def _obs_from(saved: dict):
    """The observation :func:`_obs_laid_out` saved, laid out as it was."""
    arrays = {key: _as_laid_out(value) for key, value in saved.items()}
    return arrays[""] if list(arrays) == [""] else arrays


def _in_memory_order(array: np.ndarray) -> dict:
    """An array as its bytes lie (``memory``) and the axes that view it as it is (``axes``):
    SB3 hands the policy images transposed to channels-first (a view), and a convolution of a
    view rounds differently from one of a copy, so the resumed run's first observation must be
    laid out as the uninterrupted run's was."""
    order = np.argsort([-stride for stride in array.strides], kind="stable")
    return {"memory": np.ascontiguousarray(array.transpose(order)), "axes": np.argsort(order)}


def _as_laid_out(saved: dict) -> np.ndarray:
    return saved["memory"].transpose(saved["axes"])


def _fitting(obs, space, num_envs: int):
    """``obs``, if it is a batch of ``num_envs`` observations of ``space`` (shapes and
    dtypes); else ValueError."""
    import gymnasium as gym

    spaces = space.spaces if isinstance(space, gym.spaces.Dict) else {"": space}
    arrays = obs if isinstance(obs, dict) else {"": obs}
    if set(arrays) != set(spaces):
        raise ValueError(f"an observation of {sorted(arrays)}, not {sorted(spaces)}")
    for key, sub in spaces.items():
        if (arrays[key].shape != (num_envs, *sub.shape)
                or arrays[key].dtype != np.dtype(sub.dtype)):
            raise ValueError(f"observation {key!r} is {arrays[key].dtype} of shape "
                             f"{arrays[key].shape}, not {sub.dtype} of {(num_envs, *sub.shape)}")
    return obs


def restore_progress(model, venv, folder: Path) -> bool:
    """Give a freshly built ``model`` and ``venv`` (their weights and statistics restored) the
    rest of a checkpoint (``resume.json``), so that ``model.learn`` goes on exactly where the
    run was; False for a checkpoint of an older version without it (the run then goes on
    from fresh episodes)."""
    import torch

    path = Path(folder) / RESUME
    saved = checkpoint_data.load(path, {}, RESUME_FORMAT)
    if saved is None:
        return False
    try:
        venv.unwrapped.set_state(saved["env"])
        torch.set_rng_state(torch.from_numpy(saved["rng"]["torch"]))
        np.random.set_state(saved["rng"]["numpy"])
        random.setstate(saved["rng"]["python"])
        model._last_obs = _fitting(_obs_from(saved["last_obs"]), model.observation_space,
                                   model.n_envs)  # (the model's: images channels-first)
        model._last_episode_starts = saved["last_episode_starts"]
        model._last_original_obs = saved["last_original_obs"]
        pending = saved["pending_log"]
        model.logger.name_to_value.update(pending["values"])
        model.logger.name_to_count.update(pending["counts"])
        model.logger.name_to_excluded.update(pending["excluded"])
    except (KeyError, IndexError, TypeError, ValueError, RuntimeError, AttributeError) as error:
        raise CorruptFile(path, f"not this run's state ({type(error).__name__}: "
                                f"{str(error)[:200]})") from None
    return True


def latest(checkpoint_dir: Path) -> Path | None:
    """The latest complete checkpoint's folder, or None when the run has none."""
    pointer = Path(checkpoint_dir) / FOLDER / LATEST
    if not os.path.lexists(pointer):
        return None
    name = read_json(pointer).get("folder")
    folder = pointer.parent / str(name)
    if not (isinstance(name, str) and SAVE_NAME.fullmatch(name) and not name.endswith(".partial")
            and is_regular(folder / "state.json")):
        raise CorruptFile(pointer, f"names no checkpoint of this run ({name!r})")
    return folder


def restore(model, venv, folder: Path, with_optimizer: bool = True) -> dict:
    """Give a freshly built ``model`` (and its ``venv``) a checkpoint's numbers; returns the
    checkpoint's state (``wall``, ``metrics``, ...). ``with_optimizer`` False: the policy's
    weights and the statistics only, all that playing the policy back needs (a shipped run
    folder keeps no ``optimizer.pt`` or ``resume.json``)."""
    import torch

    targets = [("policy.pt", model.policy)]
    if with_optimizer:
        targets.append(("optimizer.pt", model.policy.optimizer))
    for name, target in targets:
        try:
            with open_stored_zip(folder / name, "weights") as file:
                weights = torch.load(file, map_location="cpu", weights_only=True)
            target.load_state_dict(weights)
        except UnsafeFile:
            raise
        except (OSError, RuntimeError, ValueError, KeyError, EOFError, zipfile.BadZipFile,
                pickle.UnpicklingError) as error:
            text = ANSI.sub("", str(error)).strip()
            message = text.splitlines()[0] if text else ""
            raise CorruptFile(folder / name, f"not this run's weights ({type(error).__name__}"
                                             f": {message[:200]})") from None
    if os.path.lexists(folder / "normalize.npz"):
        _restore_stats(venv, folder / "normalize.npz")
    state = read_json(folder / "state.json")
    try:
        model.num_timesteps = int(state["num_timesteps"])
        model._n_updates = int(state["n_updates"])
        state["wall"], state["metrics"] = float(state["wall"]), dict(state["metrics"])
    except (KeyError, TypeError, ValueError) as error:
        kind = type(error).__name__
        raise CorruptFile(folder / "state.json", f"not a checkpoint's state ({kind}: "
                                                 f"{error})") from None
    return state
