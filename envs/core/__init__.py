"""The env core: the batched bodies (:class:`~animat.envs.core.batch.BodyBatch`: state, step,
observation, reward), the Gymnasium envs over it (:mod:`.env`: single and native vector, bit for
bit alike) and the sensor seam (:mod:`.sensors`).

May import tasks (its peer: a task reads the core's ``World``), vision, motor, render, physics,
bodies and checks; imported by world and registration.
"""
