"""Figure videos are H.264 in yuv420p (what browsers play), written whole or not at all."""

import subprocess

import numpy as np
import pytest
from moviepy.config import FFMPEG_BINARY

from animat.experiments.figures.video import H264Video


def _stream(path) -> str:
    probe = subprocess.run([FFMPEG_BINARY, "-i", str(path)],
                           capture_output=True, text=True)
    return next(line for line in probe.stderr.splitlines() if "Video:" in line)


def test_a_video_is_h264_in_yuv420p_with_every_frame(tmp_path):
    path = tmp_path / "clip.mp4"
    frames = [np.full((48, 64, 3), 10 * k, np.uint8) for k in range(12)]
    with H264Video(path, 20) as video:
        for frame in frames:
            video.write(frame)
    stream = _stream(path)
    assert "h264" in stream and "yuv420p" in stream and "64x48" in stream
    assert not (tmp_path / "clip.partial.mp4").exists()


def test_a_video_that_fails_midway_leaves_no_file(tmp_path):
    path = tmp_path / "clip.mp4"
    with pytest.raises(RuntimeError), H264Video(path, 20) as video:
        video.write(np.zeros((48, 64, 3), np.uint8))
        raise RuntimeError("the run broke")
    assert list(tmp_path.iterdir()) == []
