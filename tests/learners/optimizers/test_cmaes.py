"""CMA-ES's ask/tell (animat.learners.optimizers.cmaes): a candidate whose body diverged (a
non-finite energy) ranks last and the search goes on."""

import numpy as np

from animat.learners.optimizers import cmaes


def test_a_diverged_candidate_ranks_last_and_the_search_goes_on():
    params = cmaes.CMAESParams(popsize=8, sigma0=0.3)
    state = cmaes.init(params, np.full(4, 0.5), seed=0)
    for _ in range(5):
        candidates, state = cmaes.ask(params, state)
        energies = ((np.asarray(candidates) - 0.2) ** 2).sum(axis=1)
        energies[:2] = [np.nan, np.inf]
        state = cmaes.tell(params, state, candidates, energies)
    assert np.isfinite(state.told[-1]).sum() == 6 and np.isinf(state.told[-1][:2]).all()
    best = cmaes.strategy(state).result.fbest
    assert np.isfinite(best) and best < ((np.full(4, 0.5) - 0.2) ** 2).sum()
