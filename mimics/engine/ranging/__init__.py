"""Ray casting for the range finders: the engine's biggest part, behind one face.

The step uses only what is named here: a :class:`Scanner` traces a run's
scans on demand, against the walls indexed once per map
(:func:`shared_wall_index`) and the robots' index of the step. Inside, in
the order a scan goes through them:

- ``scanner.py``: which rows to trace, when, with their noise;
- ``ranger.py``: the entry points (:func:`cast_rays`, ``trace_beams``) and
  the helper threads' share of a trace;
- ``ray_kernel.py``: the compiled kernel over chunks of rows, which
  ``beam_sweep.py`` (one segment against a block of beams) and
  ``beam_fan.py`` (a robot's beams as angular fans) serve;
- ``wall_index.py`` and ``wall_occlusion.py``: the walls near each cell,
  without those hidden behind nearer ones;
- ``still_scans.py`` and ``point_cull.py``: what robots standing still can
  see, kept between steps.

The grids they walk (``spatial_index.py``, ``robot_index.py``) and the
helper threads (``mimics.engine.helper_threads``) are shared with the
collision checks, so they live beside the step, not in here.
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from mimics.engine.ranging.beam_fan import FAN_COLUMNS, beam_fans, offset_units
    from mimics.engine.ranging.ranger import RangerQuery, cast_rays
    from mimics.engine.ranging.scanner import Scanner
    from mimics.engine.ranging.wall_index import WallIndex, build_wall_index, shared_wall_index

# Each name is loaded on first use, from its module: ``state.py`` takes the beams' fans
# from ``beam_fan`` while the scanner reads ``WorldState``, so importing everything here
# at once would make the two import each other.
_HOMES = {"FAN_COLUMNS": "beam_fan", "beam_fans": "beam_fan", "offset_units": "beam_fan",
          "RangerQuery": "ranger", "cast_rays": "ranger", "Scanner": "scanner",
          "WallIndex": "wall_index", "build_wall_index": "wall_index",
          "shared_wall_index": "wall_index"}
__all__ = ["FAN_COLUMNS", "RangerQuery", "Scanner", "WallIndex", "beam_fans", "build_wall_index",
           "cast_rays", "offset_units", "shared_wall_index"]


def __getattr__(name: str) -> object:
    if name not in _HOMES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(import_module(f"{__name__}.{_HOMES[name]}"), name)
