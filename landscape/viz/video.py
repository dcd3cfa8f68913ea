"""A trial you can watch (edge layer): its trace replayed in pybullet (:mod:`sim.replay`), each frame captioned with
the time, the wing and leg angles and the potential energy, written as MP4 (H.264 through the ffmpeg that the
``imageio-ffmpeg`` wheel ships) or as an animated GIF. Everything runs offline and without a display.

The video plays in real time: frame k shows the trace row nearest ``t_0 + k / fps``, so a trace from ``t_0`` to
``t_1`` gives ``floor((t_1 - t_0) fps) + 1`` frames lasting that many ``1 / fps`` s.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from geometry.errors import UsageError

__all__ = ["VIDEO_SUFFIXES", "VideoError", "check_video_path", "write_trial_video"]

VIDEO_SUFFIXES = (".mp4", ".gif")
MJ_PER_J = 1e3


class VideoError(UsageError):
    """A video cannot be written where or how it was asked for (a ValueError: exit status 2 at the command line)."""


def check_video_path(path: str | Path) -> Path:
    """``path`` if a video can be written there: a known suffix, not a directory, its folder writable.

    Raises
    ------
    VideoError
        Naming what is wrong and the fix.

    Examples
    --------
    >>> check_video_path("trial.avi")
    Traceback (most recent call last):
    ...
    landscape.viz.video.VideoError: video trial.avi: unknown format '.avi'; name the file .mp4 (H.264) or .gif
    """
    import os
    import tempfile

    p = Path(path)
    if p.suffix.lower() not in VIDEO_SUFFIXES:
        raise VideoError(
            f"video {p}: unknown format {p.suffix or '(no suffix)'!r}; name the file .mp4 (H.264) or .gif"
        )
    if p.is_dir():
        raise VideoError(f"video {p} is a directory; give a file name ending in .mp4 or .gif")
    probe = p.parent if str(p.parent) else Path(".")
    while not probe.exists():
        probe = probe.parent
    if not probe.is_dir():
        raise VideoError(f"video {p}: {probe} is a file, not a directory; choose another path")
    if p.exists() and not os.access(p, os.W_OK):
        raise VideoError(f"video {p} is read-only; choose another path")
    try:  # a real file in the nearest existing folder: os.access says yes to root even on read-only mounts
        with tempfile.NamedTemporaryFile(dir=probe, prefix=".video-probe-"):
            pass
    except OSError as exc:
        raise VideoError(
            f"video {p} is not writable ({probe}: {exc.strerror or exc}); choose another path"
        ) from None
    return p


def _font(size_px: int):
    from PIL import ImageFont

    return ImageFont.load_default(size=size_px)


def caption_lines(t_s: float, wing_deg: float, leg_deg: float, energy_j: float) -> list[str]:
    """The caption of one frame.

    Examples
    --------
    >>> caption_lines(1.234, -0.004, -29.5, 0.04799)
    ['t = 1.23 s', 'wing 0.0°  leg -29.5°', 'energy 48.0 mJ']
    """
    w, leg = round(float(wing_deg), 1) + 0.0, round(float(leg_deg), 1) + 0.0  # no "-0.0"
    return [f"t = {t_s:.2f} s", f"wing {w:.1f}°  leg {leg:.1f}°", f"energy {energy_j * MJ_PER_J:.1f} mJ"]


def _captioned(rgb: NDArray[np.uint8], lines: list[str], title: str, font) -> NDArray[np.uint8]:
    from PIL import Image, ImageDraw

    img = Image.fromarray(rgb)
    draw = ImageDraw.Draw(img, "RGBA")
    pad = 6
    text = "\n".join([title, *lines] if title else lines)
    box = draw.multiline_textbbox((pad, pad), text, font=font, spacing=3)
    draw.rectangle(
        (box[0] - pad // 2, box[1] - pad // 2, box[2] + pad // 2, box[3] + pad // 2),
        fill=(255, 255, 255, 200),
    )
    draw.multiline_text((pad, pad), text, fill=(0, 0, 0, 255), font=font, spacing=3)
    return np.asarray(img)


def write_trial_video(
    trace,
    path: str | Path,
    *,
    robot: str | Path | None = None,
    joint_map=None,
    fps: float = 25.0,
    title: str = "",
    width_px: int = 480,
    height_px: int = 352,
) -> Path:
    """Render a trial's trace as a video.

    Parameters
    ----------
    trace : sim.trial.Trace
        The trial's trace (``run_trial(..., trace=True).trace``).
    path : path
        ``.mp4`` or ``.gif`` file to write; its folder is created.
    robot, joint_map
        The URDF and joint map the trial ran (as given to :func:`sim.trial.run_trial`).
    fps : float
        Frames per second, in (0, 100] (the trace's rate).
    title : str
        First caption line (e.g. the robot and the outcome).
    width_px, height_px : int
        Frame size, pixels; multiples of 16 (H.264's macroblocks).

    Returns
    -------
    Path

    Raises
    ------
    VideoError
        If the suffix is not .mp4/.gif, the place is not writable, the size is not a multiple of 16, or the
        trace is empty.
    """
    import imageio.v2 as iio2

    from sim.replay import frame_rows, replay_frames

    path = check_video_path(path)
    if int(width_px) % 16 or int(height_px) % 16 or min(int(width_px), int(height_px)) < 16:
        raise VideoError(f"frame size must be positive multiples of 16 pixels; got {width_px} x {height_px}")
    if trace is None or len(trace.t_s) == 0:
        raise VideoError("the trial recorded no trace to draw; run it with trace=True for at least 10 ms")
    rows = frame_rows(trace.t_s, fps)
    font = _font(max(12, int(round(height_px / 24))))
    frames = replay_frames(
        trace.pitch_deg[rows],
        trace.roll_deg[rows],
        trace.com_height_m[rows],
        trace.wing_deg[rows],
        trace.leg_deg[rows],
        robot=robot,
        joint_map=joint_map,
        width_px=width_px,
        height_px=height_px,
    )
    path.parent.mkdir(parents=True, exist_ok=True)
    if path.suffix.lower() == ".gif":
        writer = iio2.get_writer(path, format="GIF", mode="I", duration=1000.0 / fps, loop=0)
    else:
        writer = iio2.get_writer(
            path,
            format="FFMPEG",
            mode="I",
            fps=fps,
            codec="libx264",
            quality=7,
            macro_block_size=16,
            ffmpeg_log_level="error",
        )
    try:
        for row, rgb in zip(rows, frames, strict=True):
            lines = caption_lines(
                trace.t_s[row], trace.wing_deg[row], trace.leg_deg[row], trace.energy_j[row]
            )
            writer.append_data(_captioned(rgb, lines, title, font))
    except BaseException as exc:
        try:
            writer.close()
        except OSError:
            pass
        path.unlink(missing_ok=True)
        if isinstance(exc, OSError):
            raise VideoError(
                f"video {path} could not be written ({exc.strerror or exc}); choose another path"
            ) from None
        raise
    writer.close()
    return path
