"""The line's figures along the chainage: the height profile of both wires, and e(x) as built.

:func:`plot_profile` draws the contact wire and the wire the droppers hang from (messenger or stitch
wire) at every mast and dropper, with the section boundaries, the curves and the masts where the
contact-wire height changes marked; :func:`plot_elasticity_along` draws the elasticity e(x) of every span
as built at the band-centre F_m with each span's uniformity factor. :func:`embedded` puts a figure in a
page as an inline PNG.
"""

from __future__ import annotations

import base64
import tempfile
from collections.abc import Callable
from pathlib import Path

import numpy as np

from presag_opt.design.line_results import LineDesign
from presag_opt.report.html import _e
from presag_opt.style import new_figure, save_figure, styled


@styled
def plot_profile(design: LineDesign, path: str | Path) -> Path:
    """Save the height profile of both wires along the chainage.

    Parameters
    ----------
    design : LineDesign
        The line as built.
    path : str or Path
        Output file; the suffix sets the format.
    """
    fig, ax = new_figure(1, 1, width=10.0, height=4.5)
    by_id = {m.mast: m for m in design.survey.masts}
    for i, sec in enumerate(design.sections):
        masts = sec.spans
        x_mast = [s.chainage for s in masts] + [masts[-1].chainage + masts[-1].length]
        cw_mast = [by_id[s.from_mast].contact_wire_height for s in masts] + [by_id[masts[-1].to_mast].contact_wire_height]
        mw_mast = [by_id[s.from_mast].contact_wire_height + by_id[s.from_mast].system_height for s in masts]
        mw_mast.append(by_id[masts[-1].to_mast].contact_wire_height + by_id[masts[-1].to_mast].system_height)
        drop = sec.droppers
        # each wire through its masts and droppers in chainage order
        xs = np.array(x_mast + [d.chainage for d in drop])
        order = np.argsort(xs, kind="stable")
        cw = np.array(cw_mast + [d.contact_wire_height for d in drop])[order]
        mw = np.array(mw_mast + [d.messenger_height for d in drop])[order]
        first = i == 0
        ax.plot(xs[order], cw, "-", color="C0", lw=1.0, label="contact wire" if first else None)
        ax.plot(xs[order], mw, "-", color="C1", lw=1.0, label="messenger wire" if first else None)
        ax.plot([d.chainage for d in drop], [d.contact_wire_height for d in drop], ".", color="C0", ms=2.5,
                label="droppers" if first else None)
        ax.vlines(x_mast, cw_mast, mw_mast, color="0.3", lw=0.8, label="masts" if first else None)
        for s in masts:
            a, b = by_id[s.from_mast], by_id[s.to_mast]
            if a.curve_radius:
                ax.axvspan(s.chainage, s.chainage + s.length, color="C2", alpha=0.08, lw=0)
            if abs(b.contact_wire_height - a.contact_wire_height) > 1e-6:
                ax.annotate(f"{b.mast}: {b.contact_wire_height:.2f} m", (b.chainage, b.contact_wire_height),
                            xytext=(0, -14), textcoords="offset points", ha="center", fontsize=7, color="C3")
    mark_sections(design, (ax,))
    ax.set_xlabel("chainage [m]")
    ax.set_ylabel("height above the rail [m]")
    ax.legend(loc="upper right", fontsize=8)
    return save_figure(fig, path)


@styled
def plot_elasticity_along(design: LineDesign, path: str | Path) -> Path:
    """Save e(x) of every span as built along the chainage (top) and each span's uniformity (bottom).

    Parameters
    ----------
    design : LineDesign
        The line as built.
    path : str or Path
        Output file; the suffix sets the format.
    """
    fig, (top, bottom) = new_figure(2, 1, width=10.0, height=5.5, sharex=True)
    for s in design.spans:
        if s.curve is None:
            continue
        top.plot(s.chainage + s.curve.position, s.curve.elasticity * 1e3, "-", color="C0", lw=0.9)
    top.set_ylabel("e(x) as built [mm/N]")
    mid = [s.chainage + 0.5 * s.length for s in design.spans]
    bottom.bar(mid, [s.uniformity for s in design.spans], width=[0.8 * s.length for s in design.spans], color="C1")
    bottom.set_ylabel("uniformity [-]")
    bottom.set_xlabel("chainage [m]")
    mark_sections(design, (top, bottom))
    return save_figure(fig, path)


def mark_sections(design: LineDesign, axes) -> None:
    """Draw the boundaries between the line's sections (dashed, at each later section's first mast) on axes
    whose x is the chainage.

    Parameters
    ----------
    design : LineDesign
        The line.
    axes : sequence of matplotlib Axes
        The panels.
    """
    for sec in design.sections[1:]:
        for ax in axes:
            ax.axvline(sec.spans[0].chainage, color="0.5", lw=0.8, ls="--")


def embedded(plot: Callable[[LineDesign, Path], Path], design: LineDesign, key: str, caption: str) -> str:
    """A figure of ``plot`` as an inline PNG in a ``<figure id=key>`` with its caption.

    Parameters
    ----------
    plot : callable
        ``plot(design, path)`` saves the figure.
    design : LineDesign
        The line as built.
    key : str
        The figure's id on the page.
    caption : str
        Its caption.
    """
    with tempfile.TemporaryDirectory(prefix="presag-line-") as tmp:
        path = plot(design, Path(tmp) / f"{key}.png")
        data = base64.b64encode(path.read_bytes()).decode("ascii")
    return (f"<figure id='{_e(key)}'><img class='report-figure' src='data:image/png;base64,{data}' alt='{_e(caption)}'>"
            f"<figcaption>{_e(caption)}</figcaption></figure>")
