"""Learners that learn nothing, so that a fixed controller stands in comparisons: the hand-
designed MCs, the living world's behaviours, the active-vision pursuit policy.

May import :mod:`animat.envs` and the learners' interface (:mod:`animat.learners.base`,
:mod:`animat.learners.validation`).
"""
