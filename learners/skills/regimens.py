"""The regimens of basic training (:mod:`animat.learners.skills.basic_training`): each a list
of skills {``name``, ``env_id``, ``env_kwargs``, ``params``, and optionally ``learner``} (the
params the annealing learner's, over the run's shared ``annealing``; or, where a skill names
``learner: cmaes``, CMA-ES's), by name in :data:`REGIMENS`.

* ``fish``: the paper's "locomoting at different speeds and executing turns of different
  radii", in the default (reactive) water from the tasks' start spreads
  (:mod:`animat.envs.tasks.start`): swims at 1 and 2 BL/s and as fast as it can, each periodic
  over 1 s and refined within 25 parameters (its FFT abstraction's largest harmonics, annealed
  again); turns of 45, 90 and 180 deg to each side, each over its 4 s episode, scored on the
  heading where it ends and on having settled there (the turn task's ``final_weight``).
  The shipped ``repertoires/fish_reactive.json`` is its run's (``results/fish_basic_training``).
* ``fish_cmaes_turns``: the same skills, the turns learned by CMA-ES over the same encoding
  (a skill's ``learner``; the swims by annealing as above).
* ``fish_refined_turns``: the same skills, the turns by annealing and then annealing their FFT
  abstraction again, each scored on its worst starts (``worst_share``).
* ``fish_paper``: the regimen the shipped ``repertoires/fish.json`` was learned by (the paper's
  water, the point start, one turn angle).
* ``dolphin``: the dolphin's 5 basic motor tasks (move-forward; turns down, up, left and right,
  taken while swimming and learned by CMA-ES), two arcs and two pitch spins at speed, in the
  default (reactive) water from the start spread.
* ``dolphin_annealing``: the dolphin's 5 basic motor tasks of ``dolphin`` alone, all by
  simulated annealing (the paper's learner; ``dolphin`` learns its turns by CMA-ES).
* ``dolphin_paper``: the dolphin's 5 basic motor tasks and two arcs (the paper's water, the
  point start), which ``repertoires/dolphin.json`` was learned by.
"""

from __future__ import annotations

# A swim's controller: periodic over 1 s; after learning, its FFT abstraction's largest
# harmonics within 25 parameters are annealed again over a quarter of the skill's budget.
_SWIM = {"period": 1.0, "refine": {"share": 0.25, "threshold": 0.0, "max_parameters": 25,
                                   "step_size": 0.1}}
# A turn's controller: 21 nodes per actuator over its 4 s episode, abstracted as a mirrored
# series (it is not periodic); scored where it ends (the heading error and half a second of the
# yaw rate, squared), weighing as much as 5 s of the paper's path integral at that error would.
# On a 90 deg turn from the spread's starts, with 1.5-3 M env steps: 21 nodes and a weight of
# 100 learned a turn 5.7 deg off on 16 unseen starts; 11 nodes 9.1 (weight 100) and 9.6-10.2
# deg (weight 20).
_TURN = {"period": None, "nodes": 21}
_TURN_OBJECTIVE = {"duration": 4.0, "path_weight": 0.0, "final_weight": 100.0, "settle_s": 0.5}
FISH_REGIMEN = [
    *({"name": name, "env_id": "Animat/FishSwim-v0",
       "env_kwargs": {"duration": 4.0, **({"target_speed": speed} if speed else {})},
       "params": _SWIM}
      for name, speed in (("swim_slow", 1.0), ("swim_medium", 2.0), ("swim_fast", None))),
    *({"name": f"turn_{direction}_{angle}", "env_id": "Animat/FishTurn-v0",
       "env_kwargs": {**_TURN_OBJECTIVE, "angle_deg": float(angle), "direction": direction},
       "params": _TURN}
      for angle in (45, 90, 180) for direction in ("left", "right")),
]

# The fish's regimen with its turns learned by CMA-ES over the same 21 nodes (from the half
# activation, step 0.2), the swims as in FISH_REGIMEN: on the 180 deg left turn (seed 0, 2 M
# env steps) CMA-ES ended 6.4 deg off on 16 unseen starts where annealing ended 19.2.
_CMAES_TURN = {**_TURN, "popsize": 64, "sigma0": 0.2, "init": "half"}
FISH_CMAES_TURNS_REGIMEN = [
    {**spec, "learner": "cmaes", "params": _CMAES_TURN} if spec["env_id"] == "Animat/FishTurn-v0"
    else spec for spec in FISH_REGIMEN]

# The fish's regimen with its turns learned as the paper does, by annealing and then annealing
# their FFT abstraction again (the swims as in FISH_REGIMEN): 16 chains from the half
# activation, each candidate scored by the mean of its worst 4 of 8 starts, then half the
# skill's budget on the abstraction's 40 largest frequency parameters: a second search over a
# few smooth parameters, where the first's 126 nodal values fit the starts it is scored on
# (docs/fish_basic_training.md compares the two).
_REFINED_TURN = {**_TURN, "chains": 16, "init": "half", "start_states": 8, "worst_share": 0.5,
                 "refine": {"share": 0.5, "threshold": 0.0, "max_parameters": 40,
                            "step_size": 0.1}}
FISH_REFINED_TURNS_REGIMEN = [
    {**spec, "params": _REFINED_TURN} if spec["env_id"] == "Animat/FishTurn-v0" else spec
    for spec in FISH_REGIMEN]

# The regimens the shipped repertoires/fish.json and dolphin.json were learned by: in the
# paper's (resistive) water, from the point start (each episode from the task's placement).
_PAPER_WATER = {"model": "resistive"}
_PAPER = {"water": _PAPER_WATER, "start_spread": "point"}
FISH_PAPER_REGIMEN = [
    {"name": "swim_slow", "env_id": "Animat/FishSwim-v0",
     "env_kwargs": {"duration": 4.0, "target_speed": 0.4, **_PAPER},
     "params": {"period": 1.0}},
    {"name": "swim_fast", "env_id": "Animat/FishSwim-v0",
     "env_kwargs": {"duration": 4.0, **_PAPER}, "params": {"period": 1.0}},
    {"name": "turn_left_90", "env_id": "Animat/FishTurn-v0",
     "env_kwargs": {"duration": 4.0, "angle_deg": 90.0, "direction": "left",
                    **_PAPER},
     "params": {"period": None, "nodes": 11}},
    {"name": "turn_right_90", "env_id": "Animat/FishTurn-v0",
     "env_kwargs": {"duration": 4.0, "angle_deg": 90.0, "direction": "right",
                    **_PAPER},
     "params": {"period": None, "nodes": 11}},
]  # turns get 4 s: the hand turn-MC needs 2.8 s for 90 deg in this water

# The dolphin's 5 basic motor tasks (the paper's Section 4.2), each 4 s from rest 3 m down.
# Move-forward is periodic over one 5 Hz fluke beat (0.2 s, 6 nodes per actuator: a 0.4 s
# period with 10 nodes reached 1.40 BL/s on the same budget, this one 1.91); the turns span
# their episode (11 nodes), 45 deg up or down, 90 deg left or right. Then two turns taken at
# speed (the paper's "turns of different radii"): arcs of 2 BL radius down and up, periodic
# over one beat as move-forward. The pitch turns are turns from rest, whose best is a held
# bend; a somersault needs a stroke that keeps its power while it bends, which only the arcs
# have (docs/dolphin_stunts.md). Appended last, they leave the first five skills, their
# seeds (seed + index) and budgets (the run's budget over the regimen) as they were when the
# run's budget grows by theirs.
_DOLPHIN_TURN = {"period": None, "nodes": 21}
_DOLPHIN_BEAT = {"period": 0.2, "nodes": 6}  # one 5 Hz fluke beat
DOLPHIN_PAPER_REGIMEN = [
    {"name": "move_forward", "env_id": "Animat/DolphinForward-v0",
     "env_kwargs": {"duration": 4.0, **_PAPER},
     "params": _DOLPHIN_BEAT},
    *({"name": f"turn_{direction}", "env_id": "Animat/DolphinTurn-v0",
       "env_kwargs": {"duration": 4.0, "direction": direction, "angle_deg": angle,
                      **_PAPER},
       "params": _DOLPHIN_TURN}
      for direction, angle in (("down", 45.0), ("up", 45.0), ("left", 90.0), ("right", 90.0))),
    *({"name": f"arc_{direction}", "env_id": "Animat/DolphinArc-v0",
       "env_kwargs": {"duration": 4.0, "direction": direction, "radius_bl": 2.0,
                      **_PAPER},
       "params": _DOLPHIN_BEAT} for direction in ("down", "up")),
]

# The dolphin's regimen in the default (reactive) water, from the tasks' start spreads
# (envs/tasks/dolphin.py: DOLPHIN_START): move-forward from rest 3 m down, periodic over one
# 5 Hz fluke beat and refined within 25 parameters as the fish's swims; the four turns (45 deg
# down and up, 90 deg left and right) taken while swimming, from a glide at 3 m/s (1.2 BL/s)
# 8 m down, learned by CMA-ES over 21 nodes and scored where they end, as the fish's; a
# dolphin at rest yaws slowly (the hand turn-MC: 43 deg in 4 s from rest, 91 deg from the
# glide). Then the two arcs of 2 BL radius (as the paper's-water regimen), and two pitch spins
# at speed (the somersault's skill): from a 5 m/s glide pitched 45 deg toward the spin's
# opposite, 8 m down, E_v = -the pitch rate over 1 s, a periodic beat (the spin a somersault
# needs is made at speed, in the flow of the exit).
_GLIDE = {"start_speed": 3.0, "start_depth": 8.0}
DOLPHIN_REGIMEN = [
    {"name": "move_forward", "env_id": "Animat/DolphinForward-v0",
     "env_kwargs": {"duration": 4.0}, "params": {**_DOLPHIN_BEAT, "refine": _SWIM["refine"]}},
    *({"name": f"turn_{direction}", "env_id": "Animat/DolphinTurn-v0",
       "env_kwargs": {**_TURN_OBJECTIVE, **_GLIDE, "direction": direction, "angle_deg": angle},
       "learner": "cmaes", "params": _CMAES_TURN}
      for direction, angle in (("down", 45.0), ("up", 45.0), ("left", 90.0), ("right", 90.0))),
    *({"name": f"arc_{direction}", "env_id": "Animat/DolphinArc-v0",
       "env_kwargs": {"duration": 4.0, "direction": direction, "radius_bl": 2.0,
                      "start_depth": 8.0},
       "params": _DOLPHIN_BEAT} for direction in ("down", "up")),
    *({"name": f"spin_{direction}", "env_id": "Animat/DolphinSpin-v0",
       "env_kwargs": {"duration": 1.0, "direction": direction, "start_speed": 5.0,
                      "start_depth": 8.0, "start_pitch_deg": pitch},
       "params": _DOLPHIN_BEAT} for direction, pitch in (("down", 45.0), ("up", -45.0))),
]

# The paper's way in the default water: the dolphin's 5 basic motor tasks only (move-forward
# and the four turns of DOLPHIN_REGIMEN, from the same starts), every one by simulated annealing
# with the FFT abstraction, the turns as the fish's in FISH_REFINED_TURNS_REGIMEN.
DOLPHIN_ANNEALING_REGIMEN = [
    {"name": spec["name"], "env_id": spec["env_id"], "env_kwargs": spec["env_kwargs"],
     "params": _REFINED_TURN if spec["env_id"] == "Animat/DolphinTurn-v0" else spec["params"]}
    for spec in DOLPHIN_REGIMEN[:5]]

REGIMENS = {"fish": FISH_REGIMEN, "fish_cmaes_turns": FISH_CMAES_TURNS_REGIMEN,
            "fish_refined_turns": FISH_REFINED_TURNS_REGIMEN,
            "fish_paper": FISH_PAPER_REGIMEN, "dolphin": DOLPHIN_REGIMEN,
            "dolphin_paper": DOLPHIN_PAPER_REGIMEN, "dolphin_annealing": DOLPHIN_ANNEALING_REGIMEN}
