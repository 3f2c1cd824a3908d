"""Every optimiser module is an :class:`~animat.learners.optimizers.Optimizer`: it has each of
the protocol's functions with the protocol's parameters (mypy checks the types of
``OPTIMIZERS``), and keeps no code for old runs (that is ``storage/migration.py``'s)."""

import inspect

import pytest

from animat.learners.optimizers import OPTIMIZERS, Optimizer

MEMBERS = [name for name in vars(Optimizer) if not name.startswith("_")]


@pytest.mark.parametrize("name", sorted(OPTIMIZERS))
def test_each_optimizer_has_the_protocols_functions_and_parameters(name):
    module = OPTIMIZERS[name]
    assert isinstance(module.MIN_POPULATION, int) and module.MIN_POPULATION >= 1
    for member in MEMBERS:
        wanted = [p for p in inspect.signature(getattr(Optimizer, member)).parameters
                  if p != "self"]
        got = list(inspect.signature(getattr(module, member)).parameters)
        assert len(got) == len(wanted), f"{name}.{member}{tuple(got)}: wants {tuple(wanted)}"
    assert not hasattr(module, "before_schedules")


def test_the_protocol_names_what_the_loop_calls():
    assert {"init", "ask", "tell", "finished", "population", "with_population", "with_budget",
            "same_schedule", "state_bytes", "metrics", "fit_encoding",
            "refine_options"} <= set(MEMBERS)
