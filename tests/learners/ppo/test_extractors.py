"""The feature extractor sized for the compact retinal observations, named in policy_kwargs."""

import gymnasium as gym
import numpy as np
import pytest
import torch

from animat.learners.ppo.extractors import RetinaCNN
from animat.learners.ppo.zoo import PPOParams, policy_kwargs

SPACE = gym.spaces.Dict({"pixels": gym.spaces.Box(0, 255, (12, 32, 32), np.uint8),
                         "gaze": gym.spaces.Box(-1, 1, (4,), np.float32)})


def test_images_go_through_the_convolutions_and_the_rest_is_flattened_beside_them():
    net = RetinaCNN(SPACE, cnn_output_dim=64)
    assert net.features_dim == 64 + 4
    batch = {"pixels": torch.rand(5, 12, 32, 32), "gaze": torch.rand(5, 4)}
    features = net(batch)
    assert features.shape == (5, 68)
    torch.testing.assert_close(features[:, :4], batch["gaze"])  # a Dict sorts its keys
    convs = net.extractors["pixels"][0]
    assert convs(torch.zeros(1, 12, 32, 32)).shape == (1, 64 * 4 * 4)  # 32 -> 16 -> 8 -> 4


def test_a_config_names_it_and_nothing_else_unknown():
    kwargs = policy_kwargs("dict(features_extractor_class=RetinaCNN, net_arch=[256])")
    assert kwargs["features_extractor_class"] is RetinaCNN
    PPOParams(policy="MultiInputPolicy",
              policy_kwargs="dict(features_extractor_class=RetinaCNN, net_arch=[256])")
    with pytest.raises(ValueError, match="'NatureCNN' is not allowed here"):
        policy_kwargs("dict(features_extractor_class=NatureCNN)")
    with pytest.raises(ValueError, match="cnn_output_dim must be an integer >= 1"):
        RetinaCNN(SPACE, cnn_output_dim=0)
