"""A trial you can watch: frame count and duration read back, pictures that move, bad paths refused in one line."""

import contextlib
import io
from types import SimpleNamespace

import numpy as np
import pytest

pytest.importorskip("pybullet")
iio3 = pytest.importorskip("imageio.v3")

from landscape.cli import main  # noqa: E402
from landscape.viz.video import VideoError, check_video_path, write_trial_video  # noqa: E402
from sim.replay import frame_rows  # noqa: E402
from sim.trial import run_trial  # noqa: E402


def invoke(*args):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in args])
    return SimpleNamespace(exit_code=code, stdout=out.getvalue(), stderr=err.getvalue())


def _read(path):
    """Frames (K, H, W, 3) and metadata: a GIF through imageio's pillow plugin, an MP4 through the ffmpeg that
    imageio-ffmpeg ships (its frame reader leaves pipes open, which pytest turns into errors)."""
    if path.suffix == ".gif":
        return iio3.imread(path, plugin="pillow", mode="RGB"), iio3.immeta(path, plugin="pillow")
    import subprocess

    import imageio_ffmpeg

    n, secs = imageio_ffmpeg.count_frames_and_secs(str(path))
    raw = subprocess.run(
        [
            imageio_ffmpeg.get_ffmpeg_exe(),
            "-v",
            "error",
            "-i",
            str(path),
            "-f",
            "rawvideo",
            "-pix_fmt",
            "rgb24",
            "-",
        ],
        capture_output=True,
        check=True,
    ).stdout
    frames = np.frombuffer(raw, dtype=np.uint8).reshape(-1, 352, 480, 3)
    return frames, {"nframes": n, "duration": secs}


@pytest.fixture(scope="module")
def trial():
    return run_trial(74.0, 30.0, phase=0.1, cv=0.0, rng=1, duration_s=0.5, trace=True)


def test_frame_rows_closed_form():
    t = np.arange(1, 51) * 0.01  # a 0.5 s trace at 100 Hz
    np.testing.assert_array_equal(frame_rows(t, 25.0), np.arange(0, 49, 4))
    assert len(frame_rows(t, 100.0)) == 50 and len(frame_rows(t, 10.0)) == 5
    np.testing.assert_array_equal(
        frame_rows(t, 30.0)[:4], [0, 3, 7, 10]
    )  # nearest rows to 0, 33.3, 66.7, 100 ms
    with pytest.raises(ValueError, match="fps"):
        frame_rows(t, 200.0)


@pytest.mark.parametrize("suffix", ["mp4", "gif"])
def test_video_frame_count_duration_and_motion(trial, tmp_path, suffix):
    path = write_trial_video(trial.trace, tmp_path / f"trial.{suffix}", fps=25.0, title="test")
    frames, meta = _read(path)
    # rows at 0.01 .. 0.50 s: floor(0.49 * 25) + 1 = 13 frames of 40 ms
    assert frames.shape == (13, 352, 480, 3)
    if suffix == "mp4":
        assert meta["nframes"] == 13 and meta["duration"] == pytest.approx(13 / 25, abs=1e-3)
    else:
        assert meta["duration"] == pytest.approx(40.0)  # ms per frame
    assert frames[:, 60:, :].std() > 20  # not blank: ground, robot, shading
    # the caption box (top left) is light, the leg swings 30 deg: consecutive pictures differ
    assert frames[:, 8:20, 8:60].mean() > 150
    assert np.abs(frames[-1].astype(int) - frames[0].astype(int)).mean() > 1.0


def test_bad_video_paths_are_refused(tmp_path):
    with pytest.raises(VideoError, match="unknown format '.avi'"):
        check_video_path(tmp_path / "t.avi")
    (tmp_path / "file").write_text("")
    with pytest.raises(VideoError, match="is a file"):
        check_video_path(tmp_path / "file" / "t.mp4")
    (tmp_path / "d.mp4").mkdir()
    with pytest.raises(VideoError, match="is a directory"):
        check_video_path(tmp_path / "d.mp4")


@pytest.mark.parametrize(
    "video, match",
    [
        ("t.avi", "unknown format"),
        ("t", "unknown format"),
        ("file/t.mp4", "is a file"),
        ("/proc/t.mp4", "not writable"),
    ],
)
def test_simulate_video_bad_path_one_line_exit_2_before_the_trial(tmp_path, video, match):
    (tmp_path / "file").write_text("")
    target = video if video.startswith("/") else tmp_path / video
    r = invoke("simulate", "--theta-w", 74, "--theta-l", 30, "--duration", 600, "--video", target)
    assert (r.exit_code, r.stderr.count("\n")) == (2, 1), r.stderr
    assert match in r.stderr and not r.stdout  # refused before a 600 s trial ran


def test_simulate_video(tmp_path):
    r = invoke(
        "simulate",
        "--theta-w",
        74,
        "--theta-l",
        30,
        "--duration",
        0.3,
        "--seed",
        1,
        "--video",
        tmp_path / "v.gif",
    )
    assert r.exit_code == 0, r.stderr
    frames, _ = _read(tmp_path / "v.gif")
    assert len(frames) == 8 and f"video        {tmp_path / 'v.gif'}" in r.stdout  # floor(0.29 * 25) + 1
