"""Ask/tell optimisers with explicit params and state: simulated annealing (the paper's) and
CMA-ES; :mod:`animat.learners.blackbox` runs either in one loop.

Pure NumPy (and pycma): imports no env.
"""
