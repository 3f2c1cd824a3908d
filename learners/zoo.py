"""PPO's hyperparameters as rl-baselines3-zoo writes them, parsed by one pydantic model.

:class:`PPOParams` takes the zoo's names and its value forms as they appear in its YAML files:
``learning_rate: lin_3e-4`` and ``clip_range: lin_0.2`` (linear schedules to 0) as well as
numbers; ``normalize: true``, ``false``, a mapping or the zoo's string
``"{'norm_obs': True, 'norm_reward': False}"`` (VecNormalize's keywords); ``policy_kwargs`` as a
mapping or the zoo's string ``"dict(activation_fn=nn.Tanh, net_arch=dict(pi=[64], vf=[64]))"``
(literals, ``dict(...)`` and ``nn.<Module>`` names only: nothing else is evaluated). Values are
kept as written (they go into run folders as such); :func:`schedule`,
:func:`normalize_kwargs` and :func:`policy_kwargs` turn them into what SB3 takes.
"""

from __future__ import annotations

import ast

from pydantic import BaseModel, ConfigDict, Field, field_validator

NORMALIZE_KEYS = {"norm_obs", "norm_reward", "clip_obs", "clip_reward", "epsilon"}


def schedule(value: float | str):
    """A number, or the zoo's ``lin_<x>``: x times the progress remaining (1 -> 0)."""
    if isinstance(value, str):
        start = float(value.removeprefix("lin_"))
        return lambda progress_remaining: progress_remaining * start
    return float(value)


def normalize_kwargs(value: bool | dict | str) -> dict | None:
    """VecNormalize's keywords, or None for no normalisation."""
    if isinstance(value, str):
        value = ast.literal_eval(value)
    if value is False:
        return None
    return {} if value is True else dict(value)


def _evaluate(node: ast.AST):
    """Literals, lists, tuples, dicts, ``dict(k=v)``, ``-x`` and ``nn.<Module>`` names."""
    if isinstance(node, ast.Constant):
        return node.value
    if isinstance(node, (ast.List, ast.Tuple)):
        items = [_evaluate(e) for e in node.elts]
        return items if isinstance(node, ast.List) else tuple(items)
    if isinstance(node, ast.Dict):
        return {_evaluate(k): _evaluate(v) for k, v in zip(node.keys, node.values)}
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
        return -_evaluate(node.operand)
    if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "dict"
            and not node.args):
        return {kw.arg: _evaluate(kw.value) for kw in node.keywords}
    if isinstance(node, ast.Attribute):
        import torch.nn as nn

        found = getattr(nn, node.attr, None)
        owner = ast.unparse(node.value)
        if owner in ("nn", "th.nn", "torch.nn") and isinstance(found, type) and issubclass(
                found, nn.Module):
            return found
    raise ValueError(f"{ast.unparse(node)!r} is not allowed here (literals, dict(...) and "
                     "nn.<Module> only)")


def policy_kwargs(value: dict | str) -> dict:
    """The policy's keywords from a mapping or the zoo's ``dict(...)`` string."""
    if isinstance(value, dict):
        return value
    try:
        tree = ast.parse(str(value), mode="eval").body
    except SyntaxError:
        raise ValueError(f"policy_kwargs {value!r} is not a Python expression") from None
    kwargs = _evaluate(tree)
    if not isinstance(kwargs, dict):
        raise ValueError(f"policy_kwargs must look like dict(key=value, ...), got {value!r}")
    return kwargs


class PPOParams(BaseModel):
    """rl-baselines3-zoo's names and value forms with this project's defaults, plus
    ``eval_every`` (env steps between evaluations), ``torch_threads`` and
    ``checkpoint_every`` (env steps)."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    n_envs: int = Field(64, ge=1)
    n_steps: int = Field(64, ge=1)
    batch_size: int = Field(1024, ge=1)
    n_epochs: int = Field(10, ge=1)
    gamma: float = Field(0.99, gt=0.0, le=1.0)
    gae_lambda: float = Field(0.95, ge=0.0, le=1.0)
    learning_rate: float | str = 3e-4
    clip_range: float | str = 0.2
    ent_coef: float = 0.0
    vf_coef: float = 0.5
    max_grad_norm: float = 0.5
    policy: str = "MlpPolicy"
    policy_kwargs: str | dict = "dict(net_arch=[128, 128], log_std_init=-1.0)"
    normalize: bool | dict | str = True
    eval_every: int = Field(50_000, ge=1)
    torch_threads: int = Field(1, ge=1)
    checkpoint_every: int = Field(200_000, ge=1)

    @field_validator("learning_rate", "clip_range")
    @classmethod
    def _schedule(cls, value):
        if isinstance(value, str):
            try:
                if not value.startswith("lin_") or float(value[4:]) <= 0:
                    raise ValueError
            except ValueError:
                raise ValueError(f"use a number or lin_<x> (x > 0), got {value!r}") from None
        elif value <= 0:
            raise ValueError(f"must be > 0, got {value!r}")
        return value

    @field_validator("normalize")
    @classmethod
    def _normalize(cls, value):
        try:
            kwargs = normalize_kwargs(value)
        except (ValueError, SyntaxError):
            raise ValueError(f"use true, false or a mapping, got {value!r}") from None
        if kwargs is not None and not set(kwargs) <= NORMALIZE_KEYS:
            raise ValueError(f"unknown VecNormalize keys {sorted(set(kwargs) - NORMALIZE_KEYS)}"
                             f"; known: {sorted(NORMALIZE_KEYS)}")
        return value

    @field_validator("policy_kwargs")
    @classmethod
    def _policy_kwargs(cls, value):
        policy_kwargs(value)
        return value
