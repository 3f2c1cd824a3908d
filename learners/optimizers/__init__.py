"""Ask/tell optimisers with explicit params and state: simulated annealing (the paper's),
CMA-ES, and a coordinate search over discrete genes; :mod:`animat.learners.blackbox` runs any
of them in one loop.

Pure NumPy (and pycma): imports no env.
"""
