"""The coordinate search over discrete genes (animat.learners.optimizers.coordinate): it descends
to a point no single gene can improve and then stops, tries only codes the incumbent does not
hold, never keeps a diverged score, and resumes from its checkpoint data bit for bit."""

import numpy as np
import pytest

from animat.learners.blackbox_run import CHECKPOINT_TYPES
from animat.learners.optimizers import coordinate
from animat.learners.storage.checkpoint_data import from_data, to_data

LEVELS = 5
TARGET = np.array([0, 4, 2, 3, 1, 2])


def energy(x: np.ndarray) -> np.ndarray:
    """A separable energy over codes, lowest (0) at TARGET."""
    return (np.abs(coordinate.code_of(x, LEVELS) - TARGET) ** 2).sum(axis=-1).astype(float)


def search(params, state, rounds=1000, stop_after=None):
    for k in range(rounds):
        if coordinate.finished(params, state) or k == stop_after:
            break
        proposals, state = coordinate.ask(params, state)
        state = coordinate.tell(params, state, proposals, energy(proposals))
    return state


def test_it_descends_to_the_optimum_and_stops_after_a_sweep_that_changes_nothing():
    params = coordinate.CoordinateParams(levels=LEVELS)
    state = search(params, coordinate.init(params, np.zeros(len(TARGET)), seed=0))
    assert coordinate.finished(params, state)
    np.testing.assert_array_equal(coordinate.code_of(state.x, LEVELS), TARGET)
    assert state.energy == 0.0
    # a separable energy is solved in one sweep; the second confirms it: 2 sweeps of 6 genes
    assert (state.sweep, state.round) == (2, 2 * len(TARGET))


def test_a_round_tries_other_codes_of_one_gene_and_fewer_when_the_budget_affords_fewer():
    params = coordinate.CoordinateParams(levels=LEVELS)
    state = coordinate.init(params, np.full(len(TARGET), 0.5), seed=1)
    first, state = coordinate.ask(params, state)
    assert len(first) == 1  # the starting point is scored alone
    state = coordinate.tell(params, state, first, energy(first))
    proposals, _ = coordinate.ask(params, state)
    changed = np.flatnonzero((proposals != state.x).any(axis=0))
    assert len(changed) == 1 and len(proposals) == LEVELS - 1 == coordinate.population(params)
    codes = coordinate.code_of(proposals[:, changed[0]], LEVELS)
    assert sorted(codes) == [c for c in range(LEVELS) if c != 2]
    fewer = coordinate.with_population(params, 2)
    proposals, _ = coordinate.ask(fewer, state)
    codes = coordinate.code_of(proposals[:, changed[0]], LEVELS)
    assert len(proposals) == 2 == coordinate.population(fewer) and 2 not in codes
    assert len(set(codes.tolist())) == 2


def test_a_diverged_proposal_is_never_kept_and_a_diverged_start_is_refused():
    params = coordinate.CoordinateParams(levels=LEVELS)
    state = coordinate.init(params, np.zeros(len(TARGET)), seed=0)
    with pytest.raises(ValueError, match="starting point's energy is not finite"):
        coordinate.tell(params, state, state.x[None], np.array([np.nan]))
    state = coordinate.tell(params, state, state.x[None], energy(state.x[None]))
    proposals, state = coordinate.ask(params, state)
    told = coordinate.tell(params, state, proposals, np.full(len(proposals), np.nan))
    np.testing.assert_array_equal(told.x, state.x)
    assert told.energy == state.energy and told.round == 1


def test_a_search_resumed_from_its_checkpoint_data_ends_identical():
    params = coordinate.CoordinateParams(levels=LEVELS, candidates=2)
    start = coordinate.init(params, np.zeros(len(TARGET)), seed=3)
    whole = search(params, start)
    halfway = from_data(to_data(search(params, start, stop_after=7)), CHECKPOINT_TYPES)
    resumed = search(params, halfway)
    np.testing.assert_array_equal(resumed.x, whole.x)
    assert (resumed.round, resumed.sweep, resumed.energy) == (whole.round, whole.sweep,
                                                               whole.energy)


@pytest.mark.parametrize("params, message", [({"levels": 1}, "levels must be >= 2"),
                                             ({"candidates": -1}, "candidates must be >= 0")])
def test_bad_params_are_refused_in_one_line(params, message):
    with pytest.raises(ValueError, match=message):
        coordinate.CoordinateParams(**params)
