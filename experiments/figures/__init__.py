"""The figures, video and tables a run or a shipped artefact is shown by: the paper's vision
figures (:mod:`.vision`), the dolphin's stunts (:mod:`.stunts`), the living world's video
(:mod:`.world_video`), the abstraction table of a learned repertoire
(:mod:`.abstraction_table`), and how far every shipped result moves when re-scored
(:mod:`.rescore_table`). Each is a command of ``animat`` (:mod:`animat.experiments.cli`).

May import :mod:`animat.envs`, :mod:`animat.learners` and :mod:`animat.experiments.launch`;
nothing here is imported by envs or learners.
"""
