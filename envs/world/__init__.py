"""The living marine world (the paper's Section 2): minds, the perceptual oracle, intentions,
behaviours, food, obstacles, the species and start places (:mod:`.start`), and
``Animat/MarineWorld-v0`` (:mod:`.marine_env`); and the
vision-guided pursuit in it, ``Animat/FishPursuit-v0`` (:mod:`.pursuit`: an observer with eyes,
a prey and a passer that live by the world's minds). The world steps its fish on the core
(:mod:`animat.envs.core`) and may import every room below it."""
