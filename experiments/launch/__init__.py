"""What ``animat run`` stands on: the experiment config and its checks (:mod:`.config`), the run
folder with its lock, status and resume (:mod:`.folders`), the live progress line
(:mod:`.progress`), and the configs and repertoires the package ships (:mod:`.shipped`).

May import :mod:`animat.envs` and :mod:`animat.learners`; the commands above it (``cli``,
``sweep``, ``tune``, ``compare``, ``evaluate``, :mod:`animat.experiments.figures`) import it.
"""
