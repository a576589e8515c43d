"""Static maps: wall segments ("l-obstacles") plus rectangular bounds.

>>> m = Map.box(10.0, 5.0)
>>> m.segments.shape, m.bounds
((4, 4), (0.0, 0.0, 10.0, 5.0))
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np

from mimics.world.errors import ScenarioError

Bounds = tuple[float, float, float, float]  # xmin, ymin, xmax, ymax
DEFAULT_MARGIN = 1.0  # m around the walls when a file gives no bounds


def bounds_around(segments: np.ndarray, margin: float = DEFAULT_MARGIN) -> Bounds:
    """The bounding box of the segments' ends, grown by ``margin`` on every side."""
    points = np.asarray(segments, dtype=np.float64).reshape(-1, 2)
    lo, hi = points.min(axis=0), points.max(axis=0)
    return (float(lo[0] - margin), float(lo[1] - margin), float(hi[0] + margin),
            float(hi[1] + margin))


@dataclass(frozen=True, eq=False)
class Map:
    """Wall segments ``(x1, y1, x2, y2)`` in metres and the bounds of the world.

    A robot whose centre leaves ``bounds`` has escaped. Segments are read-only.
    """

    segments: np.ndarray
    bounds: Bounds
    name: str = "map"
    source: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        segs = np.ascontiguousarray(np.asarray(self.segments, dtype=np.float64).reshape(-1, 4))
        if not np.all(np.isfinite(segs)):
            raise ScenarioError(f"map {self.name!r}: segments must be finite numbers")
        segs.setflags(write=False)
        object.__setattr__(self, "segments", segs)
        bounds = tuple(float(b) for b in self.bounds)
        if (len(bounds) != 4 or not np.all(np.isfinite(bounds))
                or not (bounds[0] < bounds[2] and bounds[1] < bounds[3])):
            raise ScenarioError(f"map {self.name!r}: bounds must be (xmin, ymin, xmax, ymax) "
                                f"with xmin < xmax and ymin < ymax, got {self.bounds!r}")
        object.__setattr__(self, "bounds", bounds)

    @classmethod
    def empty(cls, bounds: Bounds, name: str = "empty") -> Map:
        """A map with no walls."""
        return cls(np.zeros((0, 4)), bounds, name)

    @classmethod
    def box(cls, width: float, height: float, origin: tuple[float, float] = (0.0, 0.0),
            name: str = "box") -> Map:
        """A rectangular room whose four walls are also its bounds."""
        x0, y0 = origin
        x1, y1 = x0 + width, y0 + height
        segs = [(x0, y0, x1, y0), (x1, y0, x1, y1), (x1, y1, x0, y1), (x0, y1, x0, y0)]
        return cls(np.array(segs), (x0, y0, x1, y1), name)

    def with_segments(self, extra: Iterable[tuple[float, float, float, float]]) -> Map:
        """A copy with more segments."""
        extra_arr = np.asarray(list(extra), dtype=np.float64).reshape(-1, 4)
        return Map(np.vstack([self.segments, extra_arr]), self.bounds, self.name, self.source)

    @property
    def size(self) -> tuple[float, float]:
        """Width and height of the bounds (m)."""
        return self.bounds[2] - self.bounds[0], self.bounds[3] - self.bounds[1]

    def __eq__(self, other: object) -> bool:
        return (isinstance(other, Map) and self.bounds == other.bounds
                and np.array_equal(self.segments, other.segments))

    def __hash__(self) -> int:
        return hash((self.bounds, self.segments.tobytes()))

    def __repr__(self) -> str:
        return f"Map({self.name!r}, {len(self.segments)} segments, bounds={self.bounds})"
