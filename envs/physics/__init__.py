"""The solver: the frozen :class:`~animat.envs.physics.system.System` (a body, the
:class:`~animat.envs.physics.system.Water`, the step and the kernels' constants, the water packed
for the kernels in one place), the force terms as small Numba functions (:mod:`.forces`; the
pectoral fins and the body frame they are set in, :mod:`.fins`), the
symplectic-Euler integrator over batches (:mod:`.integrator`), the beach ball (:mod:`.ball`) and
the measurements of a state (:mod:`.observe`: centre of mass, momenta, frames,
proprioception). SI units throughout.

May import bodies and checks.
"""
