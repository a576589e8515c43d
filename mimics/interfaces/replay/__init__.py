"""Replay of a finished run from its folder: a Matplotlib window, or a video/GIF.

The run's ``trajectory.parquet`` (one row per robot per recorded step) is
turned into dense arrays over (recorded step, robot); a robot missing from
later rows keeps its last pose and state. A frame at simulated time ``t``
shows the last recorded step at or before ``t``, exactly as logged (no
interpolation). Frames are ``speed / fps`` simulated seconds apart, from 0 to
the end of the run (the final state is always the last frame).

Laser beams are not logged, so a replay recomputes them for the chosen robot
at each frame with the engine's ray kernel (``mimics.engine.ranging.ranger.cast_rays``)
against the walls and the other robots at their logged poses. Those beams are
noise-free (the ranger noise of the run is not logged). If the kernel cannot be
imported, beams are skipped with a one-line notice.

A run edited as it ran (``mimics.world.edits``) is drawn with the walls after
the edits of each frame's step, its beams cast against them, and the trail of
a robot an edit moved broken at the jump
(:mod:`~mimics.interfaces.replay.edits`).

Videos are written with imageio's bundled ffmpeg (imageio-ffmpeg; no system
ffmpeg needed), streamed frame by frame: H.264 for ``.mp4``/``.mkv``/``.mov``/
``.avi``, and a GIF whose palette is computed per frame (exact colours for
these flat drawings, without holding the clip in memory).

>>> from mimics.interfaces.replay import frame_times
>>> frame_times(duration=1.0, fps=10, speed=4).tolist()
[0.0, 0.4, 0.8, 1.0]

The parts: :mod:`~mimics.interfaces.replay.frames` (loading a run into dense
arrays, frame times), :mod:`~mimics.interfaces.replay.beams` (beams recomputed),
:mod:`~mimics.interfaces.replay.edits` (what a run's edits change in its replay),
:mod:`~mimics.interfaces.replay.drawing` (one frame into a renderer),
:mod:`~mimics.interfaces.replay.export` (video and GIF) and
:mod:`~mimics.interfaces.replay.window` (the interactive window).
"""

from mimics.interfaces.replay.beams import BeamCaster
from mimics.interfaces.replay.drawing import Replayer
from mimics.interfaces.replay.export import ExportResult, export_replay
from mimics.interfaces.replay.frames import (
    MAX_FRAMES,
    MOTION_COLUMNS,
    VIDEO_SUFFIXES,
    ReplayData,
    frame_times,
    open_run,
    replay_data,
    robot_motion,
)
from mimics.interfaces.replay.window import ReplayWindow

__all__ = ["MAX_FRAMES", "MOTION_COLUMNS", "VIDEO_SUFFIXES", "BeamCaster", "ExportResult",
           "ReplayData", "ReplayWindow", "Replayer", "export_replay", "frame_times", "open_run",
           "replay_data", "robot_motion"]
