"""`--video run.mp4`: MuJoCo offscreen rendering on the CPU, one frame per 1/30 s of sim time.

Rendering needs an OpenGL context: on a machine without a screen MuJoCo uses OSMesa
(MUJOCO_GL=osmesa, Debian's libosmesa6; scripts/setup_system.sh installs it), ~50 ms per
640x480 frame. The camera tracks the robot's root body from a distance derived from the model's
extent. Frames are encoded to H.264 MP4 with PyAV. Call close() (the rigs do): MuJoCo's
Renderer must be closed explicitly, its destructor raises at interpreter exit otherwise.
"""
from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import numpy as np

FPS = 30


class VideoRecorder:
    def __init__(self, model, path, *, body: int = 1, width: int = 640, height: int = 480,
                 fps: int = FPS, distance: float | None = None):
        import av
        import mujoco

        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.fps = fps
        self.frames = 0
        self._mujoco = mujoco
        # A brighter headlight than MuJoCo's default (visual options only: physics unchanged).
        model.vis.headlight.ambient[:] = 0.35
        model.vis.headlight.diffuse[:] = 0.7
        self._renderer = mujoco.Renderer(model, height=height, width=width)
        cam = mujoco.MjvCamera()
        cam.type = mujoco.mjtCamera.mjCAMERA_TRACKING
        cam.trackbodyid = int(body)
        # Far enough to see the whole robot: 2.5 x its extent (MuJoCo's stat.extent, [m]).
        cam.distance = float(distance if distance is not None else 2.5 * model.stat.extent)
        cam.azimuth, cam.elevation = 135.0, -20.0
        self._camera = cam
        self._container = av.open(str(self.path), mode="w")
        self._stream = self._container.add_stream("libx264", rate=fps)
        self._stream.width, self._stream.height = width, height
        self._stream.pix_fmt = "yuv420p"
        self._stream.time_base = Fraction(1, fps)

    def capture(self, data) -> None:
        """Renders a frame for every 1/fps of simulated time that has passed (call every tick)."""
        while self.frames <= data.time * self.fps + 1e-9:
            self._renderer.update_scene(data, camera=self._camera)
            frame = self._renderer.render()
            self._encode(frame)

    def _encode(self, rgb: np.ndarray) -> None:
        import av

        frame = av.VideoFrame.from_ndarray(np.ascontiguousarray(rgb), format="rgb24")
        frame.pts = self.frames
        for packet in self._stream.encode(frame):
            self._container.mux(packet)
        self.frames += 1

    def close(self) -> None:
        if self._container is None:
            return
        for packet in self._stream.encode():
            self._container.mux(packet)
        self._container.close()
        self._container = None
        self._renderer.close()


def maybe_recorder(path, model, **kw) -> VideoRecorder | None:
    return None if not path else VideoRecorder(model, path, **kw)
