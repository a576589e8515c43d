"""Small HTML pieces for the objects' ``_repr_html_``: tables and inline figures.

>>> table = rows_table([("robots", "3"), ("status", "<done>")])
>>> table.count("<tr>"), "&lt;done&gt;" in table
(2, True)
"""

from __future__ import annotations

import base64
import html
import io
from collections.abc import Iterable
from typing import Any


def rows_table(rows: Iterable[tuple[str, str]]) -> str:
    """``(label, value)`` rows as an HTML table (escaped)."""
    cells = "".join(f'<tr><th style="text-align:left">{html.escape(label)}</th>'
                    f'<td style="text-align:left">{html.escape(value)}</td></tr>'
                    for label, value in rows)
    return f'<table class="mimics-summary"><tbody>{cells}</tbody></table>'


def error_block(text: str) -> str:
    """An error in red, its lines kept (the source line under the message)."""
    return ('<pre class="mimics-error" style="color:#c00;white-space:pre-wrap;'
            f'font-weight:bold">{html.escape(text)}</pre>')


def png_bytes(figure: Any) -> bytes:
    """A Matplotlib figure as PNG bytes, at its own size."""
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=figure.dpi)
    return buffer.getvalue()


def figure_img(figure: Any, alt: str) -> str:
    """A Matplotlib figure as an inline ``<img>`` (a PNG data URL)."""
    data = base64.b64encode(png_bytes(figure)).decode("ascii")
    return (f'<img alt="{html.escape(alt)}" style="max-width:100%" '
            f'src="data:image/png;base64,{data}"/>')


def enable_figure_display() -> None:
    """Let a notebook show a Matplotlib ``Figure`` returned by a cell as a PNG.

    The figures here are made without pyplot (no window, no global state), so
    IPython's inline backend may never have registered them; this does, once,
    when a kernel is running (it does nothing elsewhere).
    """
    try:
        from IPython import get_ipython
    except ImportError:
        return
    shell = get_ipython()
    if shell is None:
        return
    from matplotlib.figure import Figure

    formatter = shell.display_formatter.formatters["image/png"]
    if _registered(formatter, Figure):
        return
    formatter.for_type(Figure, png_bytes)


def _registered(formatter: Any, kind: type) -> bool:
    try:
        formatter.lookup_by_type(kind)
    except KeyError:
        return False
    return True


def in_kernel() -> bool:
    """True inside a Jupyter kernel (where widgets and a progress bar belong in the cell)."""
    import sys

    if "IPython" not in sys.modules:
        return False
    from IPython import get_ipython

    shell = get_ipython()
    return shell is not None and "IPKernelApp" in getattr(shell, "config", {})
