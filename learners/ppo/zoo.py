"""PPO's hyperparameters as rl-baselines3-zoo writes them, parsed by one pydantic model.

:class:`PPOParams` takes the zoo's names and its value forms as they appear in its YAML files:
``learning_rate: lin_3e-4`` and ``clip_range: lin_0.2`` (linear schedules to 0) as well as
numbers; ``normalize: true``, ``false``, a mapping or the zoo's string
``"{'norm_obs': True, 'norm_reward': False}"`` (VecNormalize's keywords); ``policy_kwargs`` as a
mapping or the zoo's string ``"dict(activation_fn=nn.Tanh, net_arch=dict(pi=[64], vf=[64]))"``
(literals, ``dict(...)``, ``nn.<Module>`` names and the project's feature extractors
(:mod:`.extractors`, e.g. ``RetinaCNN``) only: nothing else is evaluated). Values are
kept as written (they go into run folders as such); :func:`schedule`,
:func:`normalize_kwargs` and :func:`policy_kwargs` turn them into what SB3 takes.
"""

from __future__ import annotations

import ast
import inspect
import math

from pydantic import BaseModel, ConfigDict, Field, ValidationInfo, field_validator

from animat.envs.core.arguments import MAX_NUM_ENVS

from ..validation import check_memory

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
    """Literals, lists, tuples, dicts, ``dict(k=v)``, ``-x``, ``nn.<Module>`` names and the
    feature extractors' names (:data:`animat.learners.ppo.extractors.EXTRACTORS`)."""
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
    from .extractors import EXTRACTORS

    if isinstance(node, ast.Name) and node.id in EXTRACTORS:
        return EXTRACTORS[node.id]
    if isinstance(node, ast.Attribute):
        import torch.nn as nn

        found = getattr(nn, node.attr, None)
        owner = ast.unparse(node.value)
        if owner in ("nn", "th.nn", "torch.nn") and isinstance(found, type) and issubclass(
                found, nn.Module):
            return found
    raise ValueError(f"{ast.unparse(node)!r} is not allowed here (literals, dict(...), "
                     f"nn.<Module> and the extractors {', '.join(sorted(EXTRACTORS))} only)")


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
    ``eval_every`` (env steps between evaluations), ``torch_threads`` (torch's threads),
    ``update_threads`` (torch's threads while the policy is updated, where a second core
    would otherwise idle; unset: ``torch_threads``) and ``checkpoint_every`` (env steps)."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    n_envs: int = Field(64, ge=1, le=MAX_NUM_ENVS)
    n_steps: int = Field(64, ge=1)
    batch_size: int = Field(1024, ge=1)
    n_epochs: int = Field(10, ge=1)
    gamma: float = Field(0.99, gt=0.0, le=1.0)
    gae_lambda: float = Field(0.95, ge=0.0, le=1.0)
    learning_rate: float | str = 3e-4
    clip_range: float | str = 0.2
    ent_coef: float = Field(0.0, ge=0.0)
    vf_coef: float = Field(0.5, ge=0.0)
    max_grad_norm: float = Field(0.5, gt=0.0)
    policy: str = "MlpPolicy"
    policy_kwargs: str | dict = "dict(net_arch=[128, 128], log_std_init=-1.0)"
    normalize: bool | dict | str = True
    eval_every: int = Field(50_000, ge=1)
    torch_threads: int = Field(1, ge=1)
    update_threads: int | None = Field(None, ge=1)
    checkpoint_every: int = Field(200_000, ge=1)

    @field_validator("learning_rate", "clip_range")
    @classmethod
    def _schedule(cls, value):
        if isinstance(value, str):
            try:
                if not value.startswith("lin_") or not 0 < float(value[4:]) < math.inf:
                    raise ValueError
            except ValueError:
                raise ValueError(f"use a number or lin_<x> (x > 0), got {value!r}") from None
        elif not 0 < value < math.inf:
            raise ValueError(f"must be a finite number > 0, got {value!r}")
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

    @field_validator("policy")
    @classmethod
    def _policy(cls, value):
        names = sorted(policy_classes())
        if value not in names:
            raise ValueError(f"unknown policy {value!r}; PPO takes {', '.join(names)}")
        return value

    @field_validator("policy_kwargs")
    @classmethod
    def _policy_kwargs(cls, value, info: ValidationInfo):
        check_policy_kwargs(info.data.get("policy"), policy_kwargs(value))
        return value


def policy_classes() -> dict[str, type]:
    """SB3 PPO's policies by the names a config gives (``MlpPolicy``, ...)."""
    from stable_baselines3 import PPO

    return dict(PPO.policy_aliases)


def check_policy_kwargs(policy: str | None, kwargs: dict) -> None:
    """ValueError unless the policy class named ``policy`` (None: not known yet) takes every
    keyword of ``kwargs``, and ``net_arch`` is layer widths (positive integers: one list for
    both networks, or ``pi`` and ``vf`` lists) whose networks fit this machine's memory."""
    if policy in policy_classes():
        init = inspect.signature(policy_classes()[policy].__init__).parameters
        taken = set(init) - {"self", "observation_space", "action_space", "lr_schedule"}
        if set(kwargs) - taken:
            raise ValueError(f"{policy} takes no {sorted(set(kwargs) - taken)}; it takes "
                             f"{sorted(taken)}")
    arch = kwargs.get("net_arch")
    nets = ([] if arch is None else [arch, arch] if isinstance(arch, list | tuple)
            else list(arch.values()) if isinstance(arch, dict) and set(arch) <= {"pi", "vf"}
            else None)
    if nets is None or not all(isinstance(net, list | tuple) and all(
            type(width) is int and width >= 1 for width in net) for net in nets):
        raise ValueError(f"net_arch must be layer widths (integers >= 1), as [64, 64] or "
                         f"dict(pi=[64], vf=[64]), got {arch!r:.80}")
    weights = sum(sum(a * b for a, b in zip(net, net[1:])) + (net[0] + net[-1] if net else 0)
                  for net in nets)  # at least: one input and one output each
    check_memory(16 * weights, f"net_arch {arch!r:.60} (its weights, gradients and Adam's two "
                               f"moments, float32)")
