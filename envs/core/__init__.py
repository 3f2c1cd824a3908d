"""The env core: the batched bodies (:class:`BodyBatch`: state, step, observation, reward), the
Gymnasium envs over it (single and native vector) and the sensor seam."""
