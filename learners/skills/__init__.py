"""Skills: basic training (:mod:`.basic_training`, one annealing run a skill of a regimen) and
the repertoire file it writes (:mod:`.repertoire`), from which the macro and stroke learners
compose.

May import :mod:`animat.envs` (its public names) and the learners beside it (the interface,
the black-box loop, the controllers, the logger); never :mod:`animat.experiments`.
"""
