"""Benchmarks: physics (against MuJoCo's Swimmer), the retina, the living world and vision, each
printing ratios against a reference measured in the same run.

May import :mod:`animat.envs` and :mod:`animat.learners`; imported by the CLI.
"""
