"""Figure videos in H.264 (yuv420p), the codec browsers play, written frame by frame through
moviepy's ffmpeg writer (as Gymnasium's ``RecordVideo``, which ``animat eval`` uses), to a
partial file renamed into place only when whole."""

from __future__ import annotations

from pathlib import Path

import numpy as np


class H264Video:
    """``with H264Video(path, fps) as video: video.write(rgb)`` for frames (H, W, 3) uint8 RGB,
    all of one size (even, as yuv420p needs); ``path`` appears only when the video is whole."""

    def __init__(self, path: str | Path, fps: float) -> None:
        self.path, self.fps = Path(path), float(fps)
        self.partial = self.path.with_name(self.path.stem + ".partial" + self.path.suffix)
        self._writer = None

    def __enter__(self) -> H264Video:
        return self

    def write(self, rgb: np.ndarray) -> None:
        if self._writer is None:
            from moviepy.video.io.ffmpeg_writer import FFMPEG_VideoWriter

            height, width = rgb.shape[:2]
            self._writer = FFMPEG_VideoWriter(str(self.partial), (width, height), self.fps,
                                              codec="libx264", pixel_format="yuv420p")
        self._writer.write_frame(np.ascontiguousarray(rgb, dtype=np.uint8))

    def __exit__(self, kind, error, trace) -> None:
        if self._writer is not None:
            self._writer.close()
        if kind is None and self._writer is not None:
            self.partial.replace(self.path)
        else:
            self.partial.unlink(missing_ok=True)
