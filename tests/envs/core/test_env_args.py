"""A fish env's arguments as one object: the batch's by name, the rest the task's, and the
single env's own left out where the registry reads an id's kwargs."""

from animat.envs.core.env_args import BodyArgs
from animat.envs.tasks import make_task


def test_the_batchs_arguments_by_name_and_the_rest_the_tasks():
    args = BodyArgs.of({"task": "turn", "duration": 2.0, "angle_deg": 45.0, "fins": True})
    assert (args.task, args.duration, args.fins) == ("turn", 2.0, True)
    assert args.task_kwargs == {"angle_deg": 45.0}
    assert args.make_task().angle_deg == 45.0
    assert BodyArgs.of({"sensors": ["gaze"]}).task_kwargs == {"sensors": ["gaze"]}  # the task's
    assert BodyArgs.of_single_env({"sensors": ["gaze"], "render_mode": None}).task_kwargs == {}


def test_the_clock_is_the_tasks_length_where_no_duration_is_given():
    swim = make_task("swim")
    assert BodyArgs().duration_of(swim) == swim.default_duration
    assert BodyArgs(duration=3.0).duration_of(swim) == 3.0
    physics_dt, frame_skip, duration = BodyArgs(frame_skip=20).clock()
    assert (frame_skip, duration) == (20, swim.default_duration) and physics_dt > 0
