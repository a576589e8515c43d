"""The binary frame layout shared by the replay (``/api/runs/frames``) and the live stream.

One little-endian body holds T frames of n robots, read by the page with typed
arrays (``parseFrames`` in ``static/js/frames.js``), no JSON per frame:

======== ================= ==============================================
bytes    type              content
======== ================= ==============================================
0..3     uint32            T, frames sent
4..7     uint32            n, robots
8..      float32[T]        simulated time of each frame (s)
then     float32[T, n, 3]  x, y, theta of every robot in every frame
then     uint8[T, n]       state: ``Status`` code, 7 for a robot in livelock
======== ================= ==============================================

The live stream sends each frame as such a body with T = 1.

>>> import numpy as np
>>> body = encode_frames(np.zeros(1), np.zeros((1, 2, 3)), np.zeros((1, 2), dtype=np.int8))
>>> len(body) == 8 + 4 + 24 + 2
True
"""

from __future__ import annotations

import struct

import numpy as np

from mimics.engine.state import Status

#: The state code of an active robot in a livelock (after the ``Status`` codes 0..6).
LIVELOCK_CODE = max(Status) + 1
#: The names of the state codes, in code order (the keys of ``render.STATUS_COLORS``).
STATE_NAMES = [*(s.name.lower() for s in sorted(Status)), "livelock"]


def frame_states(status: np.ndarray, livelock: np.ndarray) -> np.ndarray:
    """``Status`` codes as uint8, :data:`LIVELOCK_CODE` for active robots in a livelock."""
    states = status.astype(np.uint8)
    states[livelock & (states == 0)] = LIVELOCK_CODE
    return states


def encode_frames(times: np.ndarray, poses: np.ndarray, states: np.ndarray) -> bytes:
    """The body of ``times`` (T,), ``poses`` (T, n, 3) and ``states`` (T, n) in the layout
    of the module docstring."""
    count, robots = int(poses.shape[0]), int(poses.shape[1])
    return b"".join([struct.pack("<II", count, robots), times.astype("<f4").tobytes(),
                     poses.astype("<f4").tobytes(), states.astype(np.uint8).tobytes()])
