"""A user's sensor, defined outside the library: a depth gauge that reads one number off the
core and the kinematics, passed to an env as ``sensors=[...]`` or registered with an env id."""

import gymnasium as gym
import numpy as np


class DepthGauge:
    """Depth of the centre of mass below the start, in body lengths."""

    name = "depth"

    def space(self, core):
        return gym.spaces.Box(-1e4, 1e4, (1,), np.float32)

    def read(self, core, kinematics):
        depth = (core.state.origin[:, 2] - kinematics.com[:, 2]) / core.body.length
        return depth[:, None].astype(np.float32)
