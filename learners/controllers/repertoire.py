"""The repertoire: skills (each an FFT-abstracted controller and what it was learned for) kept
in one JSON file, readable metadata (skill, task, env, objective, duration, parameter counts,
metrics) beside the Fourier coefficients. Basic training writes it
(:mod:`animat.learners.skills.basic_training`); the macro and stroke learners compose from it.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..storage.files import atomic_write, read_text
from .abstraction import AbstractController

FORMAT = "artificial-animals repertoire 1"  # a repertoire file's "format"


@dataclass(frozen=True)
class Skill:
    """One repertoire entry: an abstracted controller and what it was learned for."""

    name: str
    controller: AbstractController
    metadata: dict

    @property
    def duration(self) -> float:
        """The duration the skill was learned over, s."""
        return float(self.metadata["duration"])


class Repertoire:
    """Named skills; saved as JSON (``save``/``load``)."""

    def __init__(self, skills: list[Skill] | None = None) -> None:
        self.skills = {skill.name: skill for skill in (skills or [])}

    def __getitem__(self, name: str) -> Skill:
        if name not in self.skills:
            raise KeyError(f"no skill {name!r} in the repertoire; it has {sorted(self.skills)}")
        return self.skills[name]

    def __len__(self) -> int:
        return len(self.skills)

    @property
    def names(self) -> list[str]:
        return sorted(self.skills)

    def add(self, skill: Skill) -> None:
        self.skills[skill.name] = skill

    def save(self, path: str | Path, replace: bool = True) -> None:
        """Write atomically as JSON (``replace`` False: FileExistsError if ``path`` exists)."""
        data = {"format": FORMAT,
                "skills": [{"name": s.name, "metadata": s.metadata,
                            "controller": s.controller.to_dict()}
                           for s in (self.skills[n] for n in self.names)]}
        atomic_write(path, lambda file: json.dump(data, file, indent=1), replace=replace)

    @classmethod
    def load(cls, path: str | Path) -> Repertoire:
        """The repertoire file at ``path``; a ValueError in one line naming it for anything
        else (not JSON, another format, no skills, a skill named twice or unreadable)."""
        try:
            data = json.loads(read_text(path, "json"))
        except json.JSONDecodeError as error:
            raise ValueError(f"{path}: not a repertoire file: not valid JSON ({error.msg} at "
                             f"line {error.lineno})") from None
        if not isinstance(data, dict) or data.get("format") != FORMAT:
            raise ValueError(f"{path}: not a repertoire file (no \"format\": \"{FORMAT}\")")
        return cls(_read_skills(data.get("skills"), path))


def _read_skills(entries, path: str | Path) -> list[Skill]:
    """The skills of a repertoire file's ``skills`` list (at least one, each name once); a
    ValueError naming the file and the entry otherwise."""
    if not isinstance(entries, list) or not entries:
        raise ValueError(f"{path}: a repertoire file's skills must be a non-empty list, got "
                         f"{entries!r:.60}")
    skills: list[Skill] = []
    for k, entry in enumerate(entries):
        name = entry.get("name") if isinstance(entry, dict) else None
        if not isinstance(name, str) or not name:
            raise ValueError(f"{path}: skill {k} has no name (a string)")
        if any(skill.name == name for skill in skills):
            raise ValueError(f"{path}: skill {name!r} appears twice; a repertoire names each "
                             f"skill once")
        try:
            if not isinstance(entry["metadata"], dict):
                raise TypeError("its metadata is not a mapping")
            controller = AbstractController.from_dict(entry["controller"])
        except (KeyError, TypeError, ValueError, IndexError, AttributeError) as error:
            raise ValueError(f"{path}: skill {name!r} cannot be read ({type(error).__name__}: "
                             f"{error})") from None
        skills.append(Skill(name, controller, entry["metadata"]))
    return skills


def kept_in_run(repertoire: Repertoire, checkpoint_dir: str | Path | None) -> Repertoire:
    """The repertoire a run composes from: on its first start ``repertoire``, saved into the
    run folder (``checkpoint_dir/repertoire.json``); resumed, the copy it began with, so that
    a resumed run and a play-back use it whatever happens to the repertoire file later."""
    if not checkpoint_dir:
        return repertoire
    copy = Path(checkpoint_dir) / "repertoire.json"
    if copy.exists():
        return Repertoire.load(copy)
    repertoire.save(copy)
    return repertoire


def check_skill_names(skills: object) -> None:
    """ValueError in one line unless ``skills`` is None (all of a repertoire's) or a non-empty
    list of distinct skill names (a learner's ``skills`` param)."""
    if skills is not None and not (
            isinstance(skills, list) and skills and all(isinstance(s, str) for s in skills)
            and len(set(skills)) == len(skills)):
        raise ValueError(f"skills must be a non-empty list of distinct skill names (or "
                         f"null: all of the repertoire's), got {skills!r:.80}")


REST = -1  # the skill index of resting (muscles relaxed): the last of a player's arrays


def switch_skills(skill: np.ndarray, clock: np.ndarray, chosen: np.ndarray,
                  durations: np.ndarray, periodic: np.ndarray, dt: float) -> None:
    """Move B bodies playing ``skill`` (B,) for ``clock`` (B,) env steps onto ``chosen`` (B,),
    in place: a skill chosen again goes on from where it is; a new one, or one that is not
    periodic and has played its ``durations`` (s; :data:`REST` last, never ended), starts
    from its beginning."""
    ended = (clock * dt >= durations[chosen]) & ~periodic[chosen]
    clock[(chosen != skill) | ended] = 0
    skill[:] = chosen


def play_skills(controllers: list, durations: np.ndarray, periodic: np.ndarray,
                skill: np.ndarray, clock: np.ndarray, dt: float, actuators: int) -> np.ndarray:
    """(B, actuators) the activations in [0, 1] due at the end of the env step of B bodies
    playing ``skill`` (B,) for ``clock`` (B,) env steps, which it then moves on by one: a
    periodic skill plays as long as it is chosen, one that is not for its ``durations`` (s),
    then rests (as :data:`REST` does)."""
    u = np.zeros((len(skill), actuators))
    t = (clock + 1) * dt
    for index in np.unique(skill[skill != REST]):
        rows = (skill == index) & (periodic[index] | (t <= durations[index]))
        if rows.any():
            u[rows] = controllers[index](t[rows])
    clock += 1
    return u
