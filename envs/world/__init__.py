"""The living marine world (the paper's Section 2): minds, the perceptual oracle, intentions,
behaviours, food, obstacles, and ``Animat/MarineWorld-v0`` (:mod:`.marine_env`)."""
