"""What ``animat run`` stands on: the experiment config and its checks (:mod:`.config`), the run
folder and its status (:mod:`.folders`), its lock (:mod:`.lock`), running and resuming it
(:mod:`.execute`), the machine's facts a run records (:mod:`.machine`: CPUs, threads, commit,
versions), the live progress line (:mod:`.progress`), and the configs and repertoires the
package ships (:mod:`.shipped`).

May import :mod:`animat.envs` and :mod:`animat.learners`; the commands above it (``cli``,
``sweep``, ``tune``, ``compare``, ``evaluate``, :mod:`animat.experiments.figures`) import it.
"""
