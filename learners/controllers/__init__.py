"""What the black-box learners search and play: tent controllers (nodal values), their FFT
abstraction, and blended concatenation of abstracted controllers.

May import :mod:`animat.envs`; imported by the learners above it.
"""
