"""The shared style of every figure: the Agg backend, the figure size and resolution, saving.

All PNGs of the project go through `pyplot()` (the non-interactive Agg backend, so no display is
needed) and `save()` (tight layout, the folder created, written atomically, the figure closed).
One resolution and one font size keep the figures of a design review alike.
"""

from __future__ import annotations

from pathlib import Path

from softcrawl.files import atomic_path

#: Resolution of every PNG (dots per inch).
DPI = 120
#: PNG metadata, pinned: no "Software" entry (matplotlib writes its version there), so the same
#: data gives the same bytes with any matplotlib, and `softcrawl replot` leaves a clean checkout.
METADATA = {"Software": None}


def pyplot():
    """matplotlib.pyplot on the Agg backend."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save(fig, path, *, rect=None, tight: bool = True, outside: bool = False) -> Path:
    """Lay out (`tight`, within `rect`), write (creating the folder) and close a figure; returns
    the path. 3D axes do not support the tight layout: pass tight=False. `outside`: the figure has
    legends outside its axes, which the saved image is grown to include."""
    plt = pyplot()
    if tight:
        fig.tight_layout(rect=rect)
    path = Path(path)
    try:
        with atomic_path(path) as temp:  # a full disk leaves the old PNG, never half a new one
            fig.savefig(temp, dpi=DPI, bbox_inches="tight" if outside else None, metadata=METADATA)
    finally:
        plt.close(fig)
    return path


def short(text, n: int = 40) -> str:
    """`text` cut to n characters with an ellipsis (legend entries)."""
    text = str(text)
    return text if len(text) <= n else text[: n - 3] + "..."


def number(v) -> float | None:
    """float(v), or None for blanks and text (CSV cells)."""
    try:
        return float(v)
    except (TypeError, ValueError):
        return None
