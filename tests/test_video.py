"""--video: an MP4 that a video library opens, one frame per 1/30 s of simulated time, and the
same physics as without it (visual geometry never touches anything)."""
import json
import subprocess
import sys

import pytest

av = pytest.importorskip("av")


def test_video_writes_an_mp4_with_one_frame_per_30th_of_a_second(tmp_path):
    video = tmp_path / "run.mp4"
    args = [sys.executable, "-m", "kiloloop.cli", "run", "arm-track", "--duration", "0.5", "--json"]
    with_video = subprocess.run(args + ["--video", str(video)], capture_output=True, text=True,
                                timeout=300)
    assert with_video.returncode == 0, with_video.stderr
    with av.open(str(video)) as container:
        stream = container.streams.video[0]
        frames = sum(1 for _ in container.decode(stream))
        assert stream.average_rate == 30
    assert frames == 15  # 0.5 s at 30 frames per second
    plain = subprocess.run(args, capture_output=True, text=True, timeout=300)
    m1, m0 = json.loads(with_video.stdout)["metrics"], json.loads(plain.stdout)["metrics"]
    assert m1 == m0
