"""Feature extractors sized for the retinal observations, by the names a config's
``policy_kwargs`` may give (:data:`EXTRACTORS`, e.g.
``dict(features_extractor_class=RetinaCNN)``).

SB3's ``MultiInputPolicy`` sends every image entry of a ``Dict`` observation through its
NatureCNN (three convolutions of 8, 4 and 3 pixels, strides 4, 2 and 1: built for 84x84 Atari
frames, too deep for 32x32 pictures and costly on 64x64 stacks). :class:`RetinaCNN` is the
small network the compact retinal sensors (``pixels``, ``evidence``:
:mod:`animat.envs.vision.pixels`) are sized for: three 3x3 convolutions of stride 2 (32, 64
and 64 channels, ReLU), which take a 32x32 picture to 4x4, then one linear layer; the
non-image entries are flattened beside it. The images arrive as the uint8 SB3 keeps in its
rollout buffer and are scaled to [0, 1] by SB3 before the network (``normalize_images``).
"""

from __future__ import annotations

import gymnasium as gym
import torch
from stable_baselines3.common.preprocessing import is_image_space
from stable_baselines3.common.torch_layers import BaseFeaturesExtractor
from torch import nn


class RetinaCNN(BaseFeaturesExtractor):
    """A ``Dict`` observation's features: each channel-first image entry (C, H, W) through
    three 3x3 convolutions of stride 2 and padding 1 (``channels``, ReLU) and a linear layer
    to ``cnn_output_dim`` (ReLU); every other entry flattened; all concatenated, (batch,
    features)."""

    def __init__(self, observation_space: gym.spaces.Dict, cnn_output_dim: int = 256,
                 channels: tuple[int, int, int] = (32, 64, 64)) -> None:
        if type(cnn_output_dim) is not int or cnn_output_dim < 1:
            raise ValueError(f"cnn_output_dim must be an integer >= 1, got {cnn_output_dim!r}")
        if len(channels) != 3 or any(type(c) is not int or c < 1 for c in channels):
            raise ValueError(f"channels must be three integers >= 1, got {channels!r}")
        nets: dict[str, nn.Module] = {}
        size = 0
        for key, space in observation_space.spaces.items():
            if is_image_space(space):  # channel-first here: SB3 transposes the others
                nets[key] = _conv_net(space.shape, cnn_output_dim, tuple(channels))
                size += cnn_output_dim
            else:
                nets[key] = nn.Flatten()
                size += int(torch.Size(space.shape).numel())
        super().__init__(observation_space, features_dim=size)
        self.extractors = nn.ModuleDict(nets)

    def forward(self, observations: dict[str, torch.Tensor]) -> torch.Tensor:
        return torch.cat([net(observations[key]) for key, net in self.extractors.items()],
                         dim=1)


def _conv_net(shape: tuple[int, ...], output: int, channels: tuple[int, ...]) -> nn.Sequential:
    """The convolutions for images of ``shape`` (C, H, W), then the linear layer to
    ``output``."""
    layers: list[nn.Module] = []
    inputs = shape[0]
    for width in channels:
        layers += [nn.Conv2d(inputs, width, 3, stride=2, padding=1), nn.ReLU()]
        inputs = width
    convs = nn.Sequential(*layers, nn.Flatten())
    with torch.no_grad():
        flat = convs(torch.zeros(1, *shape)).shape[1]
    return nn.Sequential(convs, nn.Linear(flat, output), nn.ReLU())


EXTRACTORS: dict[str, type[BaseFeaturesExtractor]] = {"RetinaCNN": RetinaCNN}
