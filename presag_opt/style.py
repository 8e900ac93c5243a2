"""The one look of every figure: the command line's ``--plot`` files, the notebooks and the HTML report.

Figure modules (:mod:`presag_opt.plotting`, :mod:`presag_opt.studies.plots`) draw inside
functions decorated with :func:`styled` (the style is in force while they draw, and only then),
create their figures with :func:`new_figure`, put legends where they cannot cover data with
:func:`legend_outside`, and write them with :func:`save_figure`; nothing else sets matplotlib
parameters. Axis labels carry their unit in brackets, ``[mm/N]``, ``[-]`` for a ratio.

Importing this module changes nothing in matplotlib: the figures are plain
:class:`matplotlib.figure.Figure` objects, never registered with pyplot (no backend is chosen, no
window opens, none piles up in a long run), and the format of a file follows its suffix.
"""

from __future__ import annotations

import contextlib
import functools
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any, TypeVar

import matplotlib
from matplotlib.axes import Axes
from matplotlib.figure import Figure

STYLE = {
    "figure.dpi": 100,
    "savefig.dpi": 130,
    "font.size": 9,
    "axes.titlesize": 9,
    "axes.labelsize": 9,
    "legend.fontsize": 8,
    "legend.frameon": False,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "lines.linewidth": 1.4,
    "axes.prop_cycle": matplotlib.cycler(color=[
        "#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000", "#F0E442",
    ]),
}
"""matplotlib parameters of every figure (a colour-blind-safe cycle, light grid, no frame on legends),
in force while a :func:`styled` function draws."""

Drawing = TypeVar("Drawing", bound=Callable[..., Any])


@contextlib.contextmanager
def drawing() -> Iterator[None]:
    """:data:`STYLE` in force for the ``with`` block that draws a figure (the caller's matplotlib
    parameters again after it)."""
    with matplotlib.rc_context(STYLE):
        yield


def styled(draw: Drawing) -> Drawing:
    """Decorator of a function that draws a figure: it runs in :func:`drawing`."""

    @functools.wraps(draw)
    def in_style(*args: Any, **kwargs: Any) -> Any:
        with drawing():
            return draw(*args, **kwargs)

    return in_style  # type: ignore[return-value]

LEGEND_WIDTH = 2.6
"""Width of the strip kept right of the axes for a legend. [inch]"""


def new_figure(rows: int = 1, cols: int = 1, *, width: float = 7.0, height: float = 3.6,
               legend: bool = False, **kwargs: Any) -> tuple[Figure, Any]:
    """A figure in the project style, with room for a legend right of the axes if ``legend``.

    Parameters
    ----------
    rows, cols : int
        Panels. [-]
    width, height : float
        Size of the panels' area. [inch]
    legend : bool
        Widen the figure by :data:`LEGEND_WIDTH` for :func:`legend_outside`.
    **kwargs
        Passed on to :meth:`matplotlib.figure.Figure.subplots` (``sharex``, ``squeeze``, ...).
    """
    fig = Figure(figsize=(width + (LEGEND_WIDTH if legend else 0.0), height))
    axes = fig.subplots(rows, cols, **kwargs)
    fig._presag_legend = legend  # read by save_figure to keep the strip free
    return fig, axes


def legend_outside(fig: Figure, ax: Axes, title: str | None = None) -> None:
    """One legend for the figure, in the strip right of the axes (never over data)."""
    handles, labels = ax.get_legend_handles_labels()
    fig.legend(handles, labels, loc="center left", bbox_to_anchor=(1.0 - LEGEND_WIDTH / fig.get_figwidth(), 0.5),
               title=title)


def save_figure(fig: Figure, path: str | Path) -> Path:
    """Lay out and save a figure; the suffix selects the format (png, pdf, svg).

    Returns
    -------
    pathlib.Path
        The file written.
    """
    path = Path(path)
    room = LEGEND_WIDTH / fig.get_figwidth() if getattr(fig, "_presag_legend", False) else 0.0
    fig.tight_layout(rect=(0.0, 0.0, 1.0 - room, 1.0))
    fig.savefig(path)
    return path
