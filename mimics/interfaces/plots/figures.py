"""The figure and PNG helpers every static plot shares."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from mimics.world.errors import MimicsError


def _new_figure(width_px: int, height_px: int, dpi: float = 100.0) -> Figure:
    if width_px < 100 or height_px < 100:
        raise MimicsError(f"plot size must be at least 100x100 pixels, got {width_px}x{height_px}")
    fig = Figure(figsize=(width_px / dpi, height_px / dpi), dpi=dpi, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def _save(fig: Figure, out: str | Path | None) -> Any:
    """Save a PNG at the figure's exact pixel size; one clear error if it cannot be written.

    ``out`` None: the figure itself is returned (for a notebook), not saved.
    """
    if out is None:
        return fig
    out = Path(out)
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(out, dpi=fig.dpi, format="png")
    except OSError as exc:
        raise MimicsError(f"cannot write {out}: {exc.strerror or exc}") from None
    return out
