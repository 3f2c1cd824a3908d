"""The experiment launcher ``animat`` (:mod:`animat.experiments.cli`) and what it runs.

Rooms: :mod:`.launch` (configs, run folders, progress, shipped files), :mod:`.figures` (the
paper's figures, the stunts, the world's video, the abstraction table) and :mod:`.bench` (the
benchmarks); beside them the commands: ``cli`` (and its ``parser``), ``sweep``, ``tune``,
``compare``, ``evaluate``, ``demo`` and ``fingerprint``. Imports run one way: experiments ->
learners -> envs.
"""
