"""Which beams a direction or an angular span covers: a ranger's fan of beams.

A robot type's beam offsets are summed up once per type (:func:`beam_fans`):
evenly spaced beams as an arithmetic layout (base angle, spacing, count), so
that the beams a segment's span covers are found by arithmetic, and the fan's
field of view as its two edge rays, so that walls and robots wholly behind a
sensor are skipped before any beam is tested. A polynomial arctangent
(:func:`fast_atan2`, error below 1.15e-5 rad) only picks beams; every span is
widened by ``ANGLE_SLACK``, so no beam that may hit is left out.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from mimics.engine.compiling.kernel_minmax import larger, smaller
from mimics.engine.compiling.kernel_options import INNER

COLLINEAR_EPS = 1e-10  # a parallel segment this close to the beam's line lies on it (m)
ANGLE_SLACK = 2e-4  # rad added around every swept span: 17x fast_atan2's error (< 1.15e-5)


MIN_SPACING = 1e-9  # rad: beams closer than this are tested one by one


TAU = 2.0 * math.pi


FAN_COLUMNS = 10  # a row of ``beam_fans``


#: ``(base angle, spacing, count, margin, 1 / spacing)`` of evenly spaced beams (``_layout``)
Layout = tuple[float, float, float, float, float]


#: ``(e0x, e0y, e1x, e1y, kind)``: the beams' field of view (``_field_of_view``)
Cone = tuple[float, float, float, float, float]


@njit(cache=True)
def fast_atan2(y: float, x: float) -> float:
    """``atan2(y, x)`` within 1.15e-5 rad, much faster than libm's.

    Only used to pick which beams a segment may hit (with ``ANGLE_SLACK`` to
    spare, a fraction of a beam: the margin of a degree-spaced fan is the same
    two beams as with an exact arctangent); the hits themselves are computed
    exactly.
    """
    ax, ay = abs(x), abs(y)
    big = larger(ax, ay)
    if big == 0.0:
        return 0.0
    a = smaller(ax, ay) / big
    s = a * a
    # atan on [0, 1], Abramowitz & Stegun 4.4.47 (error below 1.15e-5): a short chain of
    # dependent multiply-adds, two per swept segment
    r = a * (0.9998660 + s * (-0.3302995 + s * (0.1801410 + s * (-0.0851330 + s * 0.0208351))))
    if ay > ax:
        r = 0.5 * math.pi - r
    if x < 0.0:
        r = math.pi - r
    return -r if y < 0.0 else r


@njit(**INNER)
def _relative(angle: float, layout: Layout) -> float:
    """``angle`` less the first beam's, in ``[0, 2 pi)`` (up to rounding)."""
    rel = angle - layout[0]
    return rel - TAU * math.floor(rel * (1.0 / TAU))


@njit(**INNER)
def _beam_range(rel: float, span: float, layout: Layout) -> tuple[int, int]:
    """Beams whose angle less the first beam's lies in ``[rel, rel + span]``, with margin.

    Empty (first > last) when no beam is there; spans wholly before the first
    beam or after the last are told apart before any rounding to beams.
    """
    _, spacing, count, margin, per_rad = layout
    if rel + span < -(margin + 1.0) * spacing or rel > (count + margin) * spacing:
        return 1, 0
    # products by the reciprocal differ from quotients by rounding only: the margin covers it
    first = larger(math.ceil(rel * per_rad) - int(margin), 0)
    last = smaller(math.floor((rel + span) * per_rad) + int(margin), int(count) - 1)
    return first, last


@njit(**INNER)
def _turns(rel: float, span: float, layout: Layout) -> tuple[bool, bool]:
    """Whether ``[rel, rel + span]`` may also overlap the beams one turn back, one turn on.

    ``rel`` is in ``[0, 2 pi)`` (``_relative``): the span seen one turn back
    reaches the first beams when it crosses a full turn, one turn on only in
    fans of about a full turn. Most spans need neither.
    """
    _, spacing, count, margin, _ = layout
    return (rel + span - TAU >= -(margin + 1.0) * spacing,
            rel + TAU <= (count + margin) * spacing)


@njit(**INNER)
def _turn(k: int, back: bool) -> float:
    """The ``k``-th shift to try: 0, then -2 pi if ``back``, then +2 pi."""
    return 0.0 if k == 0 else (-TAU if back and k == 1 else TAU)


@njit(**INNER)
def _layout(offsets: np.ndarray) -> Layout:
    """``(first offset, spacing, count, margin, 1 / spacing)`` of a row of beams (spacing 0:
    none); a scan adds its heading to the first.

    Rows whose used beams form a prefix of increasing, near-evenly spaced
    angles spanning at most a full turn get their spacing; the margin (in
    beams) covers the deviation from even spacing, ``fast_atan2``'s error and
    rounding.
    """
    beams = offsets.shape[0]
    unordered = (offsets[0], 0.0, float(beams), 0.0, 0.0)
    count = 0
    while count < beams and not math.isnan(offsets[count]):
        count += 1
    if count < 2 or count * 2 < beams:  # few beams: one by one costs as little
        return unordered
    for j in range(count, beams):
        if not math.isnan(offsets[j]):
            return unordered  # used beams are not a prefix
    spacing = (offsets[count - 1] - offsets[0]) / (count - 1)
    if not (spacing > MIN_SPACING and spacing * (count - 1) <= TAU):
        return unordered
    deviation = 0.0
    for j in range(count):
        deviation = larger(deviation, abs(offsets[j] - (offsets[0] + j * spacing)))
    margin = 1.0 + math.ceil((deviation + ANGLE_SLACK) / spacing)
    if margin > 3.0:
        return unordered
    return (offsets[0], spacing, float(count), margin, 1.0 / spacing)


@njit(**INNER)
def _field_of_view(offsets: np.ndarray) -> Cone:
    """``(e0x, e0y, e1x, e1y, kind)``: the cone swept counterclockwise from ``e0`` to ``e1``.

    The edges point along the lowest and highest beam offsets (a scan rotates
    them to its heading like its beams, so every beam lies between them up to
    rounding, which the cull's slack covers); ``kind`` is 1
    for a cone narrower than a half turn (outside it: beyond either edge), 2
    for a wider one (outside it: beyond both) and 0 when there is no cone to
    cull by (beams in no order, or a near-full turn).
    """
    low, high, count = math.inf, -math.inf, 0
    for j in range(offsets.shape[0]):
        if not math.isnan(offsets[j]):
            low, high, count = smaller(low, offsets[j]), larger(high, offsets[j]), count + 1
    width = high - low
    if count == 0 or width >= TAU - 1e-6:
        return (1.0, 0.0, 1.0, 0.0, 0.0)
    return (math.cos(low), math.sin(low), math.cos(high), math.sin(high),
            1.0 if width < math.pi - 1e-6 else 2.0)


@njit(**INNER)
def _beyond_edges(px: float, py: float, clearance: float, cone: Cone) -> int:
    """Bits 0 and 1: ``p`` lies more than ``clearance`` beyond edge 0, 1.

    The slack covers rounding and the collinear tolerance of the hit test.
    """
    slack = clearance + 2.0 * COLLINEAR_EPS + 1e-9 * (abs(px) + abs(py))
    bits = 0
    if cone[0] * py - cone[1] * px < -slack:
        bits |= 1
    if cone[2] * py - cone[3] * px > slack:
        bits |= 2
    return bits


@njit(**INNER)
def _outside_view(a: int, b: int, kind: float) -> bool:
    """Whether a convex set whose extreme points have edge bits ``a`` and ``b`` is unseen."""
    common = a & b
    return common != 0 if kind == 1.0 else (kind == 2.0 and common == 3)


def offset_units(offsets: np.ndarray) -> np.ndarray:
    """``(..., 2)``: the cosine and sine of each beam offset (NaN for unused slots)."""
    return np.ascontiguousarray(np.stack([np.cos(offsets), np.sin(offsets)], axis=-1))


@njit(cache=True)
def beam_fans(offsets: np.ndarray) -> np.ndarray:
    """``(k, FAN_COLUMNS)``: each row of beam offsets' fan, relative to its heading.

    Columns 0-4 are its ``_layout`` (the first offset, spacing, count, margin,
    1 / spacing), 5-9 its ``_field_of_view`` (the unit vectors of the lowest
    and highest offsets, and the cone's kind). A scan adds its heading to the
    first and rotates the second: rows repeat per robot type, so a simulation
    computes them once.
    """
    fans = np.zeros((offsets.shape[0], FAN_COLUMNS))
    if offsets.shape[1] == 0:
        return fans  # no beams: no scan will read a fan
    for i in range(offsets.shape[0]):
        layout, cone = _layout(offsets[i]), _field_of_view(offsets[i])
        for c in range(5):
            fans[i, c], fans[i, 5 + c] = layout[c], cone[c]
    return fans
