"""SVG drawings to wall segments.

Every shape's outline becomes walls: lines, polylines, polygons, rects,
circles, ellipses and paths, with their transforms applied (svgelements
``reify``). Curves and arcs are flattened into straight pieces within
``tolerance`` metres. Text, images and hidden elements are ignored.

Scale: by default the drawing's own units give its physical size (``mm``,
``cm``, ``in``; 1 px = 1/96 in). With ``scale`` every SVG user unit (the
unit of the coordinates written in the file, i.e. of the ``viewBox``) is
``scale`` metres. The y axis is flipped so that up in the drawing is +y, with
the bottom-left corner of the document at the origin (the drawing's lowest
point when the document has no size).

>>> # <svg width="20" height="10"><line x1="1" y1="2" x2="5" y2="2"/></svg>
>>> # import_svg("room.svg", scale=0.5).segments  ->  [[0.5, 4.0, 2.5, 4.0]]
"""

from __future__ import annotations

import math
from pathlib import Path
from xml.etree.ElementTree import ParseError

import numpy as np
import svgelements as se
from skimage.measure import approximate_polygon

from mimics.world.errors import MimicsError
from mimics.world.maps import Map, bounds_around

# one CSS px (1/96 in) in metres, using svgelements' inches per mm so that mm and cm are exact
METRES_PER_PX = 0.001 / (se.DEFAULT_PPI * 0.0393701)
_CURVES = (se.QuadraticBezier, se.CubicBezier, se.Arc)


def _parse(path: Path) -> se.SVG:
    if not path.is_file():
        raise MimicsError(f"{path}: SVG file not found")
    try:
        svg = se.SVG.parse(str(path), reify=True)
    except ParseError as exc:
        raise MimicsError(f"{path}: not a valid SVG (XML error: {exc})") from None
    except Exception as exc:  # svgelements raises assorted errors on odd input
        raise MimicsError(f"{path}: cannot read the SVG ({type(exc).__name__}: {exc})") from None
    if not isinstance(svg, se.SVG):  # XML, but its root is not an <svg> of the SVG namespace
        raise MimicsError(f"{path}: not an SVG drawing (its root element is not <svg> in the "
                          "SVG namespace)")
    return svg


def _flatten(shape: se.Shape, tolerance_px: float) -> list[np.ndarray]:
    """Polylines ``(k, 2)`` in px of one shape's outline, curves flattened."""
    path = abs(se.Path(shape))
    pieces: list[np.ndarray] = []
    for seg in path.segments():
        if isinstance(seg, se.Move) or seg.start is None or seg.end is None:
            continue
        if isinstance(seg, _CURVES):
            length = seg.length(error=1e-6)
            samples = int(min(max(math.ceil(length / max(tolerance_px, 1e-12)), 8), 4000))
            points = np.asarray(seg.npoint(np.linspace(0.0, 1.0, samples + 1)), dtype=float)
            pieces.append(approximate_polygon(points, tolerance_px))
        elif isinstance(seg, se.Linear):  # Line and Close
            pieces.append(np.array([[seg.start.x, seg.start.y], [seg.end.x, seg.end.y]]))
    return pieces


def import_svg(path: str | Path, scale: float | None = None,
               tolerance: float | None = None) -> Map:
    """A map from the outlines of an SVG drawing's shapes.

    Args:
        path: the ``.svg`` file.
        scale: metres per SVG user unit; default: the drawing's physical units.
        tolerance: how far (m) flattened curves may stray from the true curve;
            default a thousandth of the drawing's diagonal.

    Returns:
        A map whose bounds are the document's box (expanded to hold every
        wall), or the walls' bounding box plus a margin when the document has
        no size.

    Raises:
        MimicsError: not an SVG, or a drawing with no shapes.
    """
    path = Path(path)
    if scale is not None and (isinstance(scale, bool) or not isinstance(scale, int | float)
                              or not scale > 0 or not math.isfinite(scale)):
        raise MimicsError(f"{path}: scale must be a positive number of metres per SVG unit, "
                          f"got {scale!r}")
    if tolerance is not None and (isinstance(tolerance, bool)
                                  or not isinstance(tolerance, int | float) or tolerance <= 0):
        raise MimicsError(f"{path}: tolerance must be a positive number of metres, "
                          f"got {tolerance!r}")
    svg = _parse(path)
    sized = ("width" in svg.values and "height" in svg.values) or "viewBox" in svg.values
    if scale is None:
        metres_per_px = METRES_PER_PX
    else:
        box = svg.viewbox
        px_per_unit = (min(svg.width / box.width, svg.height / box.height)
                       if box is not None and box.width and box.height else 1.0)
        metres_per_px = float(scale) / px_per_unit
    shapes = [e for e in svg.elements() if isinstance(e, se.Shape)]
    boxes = np.array([b for b in (s.bbox() for s in shapes) if b is not None]).reshape(-1, 4)
    if boxes.size == 0:
        raise MimicsError(f"{path}: the drawing has no lines or shapes to turn into walls")
    diagonal_px = math.hypot(boxes[:, 2].max() - boxes[:, 0].min(),
                             boxes[:, 3].max() - boxes[:, 1].min())
    tolerance_px = (diagonal_px * 1e-3 if tolerance is None else tolerance / metres_per_px)
    tolerance_px = max(tolerance_px, 1e-9)
    pieces = [piece for shape in shapes for piece in _flatten(shape, tolerance_px)]
    segments = np.vstack([np.hstack([p[:-1], p[1:]]) for p in pieces if len(p) >= 2]
                         or [np.zeros((0, 4))])
    segments = segments[(segments[:, 0] != segments[:, 2]) | (segments[:, 1] != segments[:, 3])]
    if len(segments) == 0:
        raise MimicsError(f"{path}: the drawing has no lines or shapes to turn into walls")
    flip_px = float(svg.height) if sized else float(segments[:, [1, 3]].max())
    world = segments * metres_per_px
    world[:, [1, 3]] = (flip_px - segments[:, [1, 3]]) * metres_per_px
    if sized:
        points = world.reshape(-1, 2)
        lo, hi = points.min(axis=0), points.max(axis=0)
        bounds = (min(0.0, lo[0]), min(0.0, lo[1]), max(float(svg.width) * metres_per_px, hi[0]),
                  max(flip_px * metres_per_px, hi[1]))
    else:
        bounds = bounds_around(world)
    return Map(world, bounds, name=path.stem, source=str(path))
