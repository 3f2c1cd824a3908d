"""What a run folder's files are made of: atomic writes and JSON read back one line at fault
(:mod:`.files`), checkpoints as data (:mod:`.checkpoint_data`), an older version's pickled
checkpoints and where their classes are now (:mod:`.pickles`).

May import :mod:`animat.envs` (its public names) and the learners whose progress a checkpoint
holds (lazily, where it is read); never :mod:`animat.experiments`.
"""
