"""The integrators' accuracy table (:mod:`animat.experiments.bench.integrators`): its figures come
from real runs, its cells say how far each is from the reference, and the implicit step
converges to the reference as its step shrinks."""


from animat.envs.bodies.fish import fish_body
from animat.envs.physics.system import DEFAULT_DT
from animat.experiments.bench.integrators import _cruise_speed, deviation, table, within_bound
from animat.experiments.bench.stability import stability


def test_the_cruise_converges_to_the_explicit_reference_as_the_step_shrinks():
    """Backward Euler is first order: in the reactive water the cruise speed's error halves
    with the step, and at 1.5625 ms both waters are within 1.5% of the converged explicit
    reference (the resistive water's residue is the explicit step's drag limiter, which the
    implicit step does without)."""
    body = fish_body()
    for model in ("reactive", "resistive"):
        reference = _cruise_speed(body, model, "explicit", DEFAULT_DT / 4, 1.0)
        errors = [abs(_cruise_speed(body, model, "implicit", dt, 1.0) - reference) / reference
                  for dt in (0.003125, 0.0015625)]
        assert errors[1] <= 0.015, (model, errors)
        if model == "reactive":
            assert 0.4 <= errors[1] / errors[0] <= 0.6, errors



def test_cells_give_percent_for_figures_and_degrees_for_angles():
    assert deviation("reactive U", 2.6, 2.0) == "2.6 (+30.0%)"
    assert deviation("reactive turn-MC heading", 80.0, 90.0) == "80.0 (-10.0°)"
    assert deviation("reactive U", float("nan"), 2.0) == "non-finite"
    assert within_bound("reactive U", 2.09, 2.0) and not within_bound("reactive U", 2.11, 2.0)
    assert within_bound("dolphin pitch turn", 80.0, 76.0)
    assert not within_bound("dolphin pitch turn", 70.0, 76.0)


def test_the_table_says_which_columns_keep_every_figure_within_the_bound():
    results = {"reference": {"reactive U": 2.0, "reactive turn-MC heading": 90.0},
               "close": {"reactive U": 2.05, "reactive turn-MC heading": 93.0},
               "far": {"reactive U": 2.5, "reactive turn-MC heading": 90.0}}
    last = table(results).splitlines()[-1]
    assert last == "| every figure within 5% (5°) | — | yes | no |"


def test_the_stability_sweep_counts_the_drives_that_keep_every_body_sound():
    rows = stability(bodies=2, seconds=0.5).splitlines()[2:]
    assert len(rows) == 4
    for row in rows:
        for cell in row.split("|")[2:-1]:
            kept, total = cell.split()[0].split("/")
            assert total == "22" and 0 <= int(kept) <= 22
