"""``presag_opt.style``: every figure in one style, with the legend in a strip right of the axes that the
layout keeps free, saved in the format its suffix names."""

from __future__ import annotations

import matplotlib
import pytest

from presag_opt import style


def test_the_style_is_in_force_while_a_figure_is_drawn_and_only_then():
    import subprocess
    import sys

    code = ("import matplotlib; before = dict(matplotlib.rcParams); import presag_opt.style, presag_opt.plotting; "
            "print(dict(matplotlib.rcParams) == before)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["True"]  # importing changes no parameter (and chooses no backend)
    seen = {}

    @style.styled
    def draw():
        seen.update(dpi=matplotlib.rcParams["savefig.dpi"], top=matplotlib.rcParams["axes.spines.top"],
                    colours=[c["color"] for c in matplotlib.rcParams["axes.prop_cycle"]][:2])

    draw()
    assert seen == {"dpi": 130, "top": False, "colours": ["#0072B2", "#D55E00"]}  # the Okabe–Ito cycle
    assert matplotlib.rcParams["savefig.dpi"] != 130  # and the caller's parameters after it


def test_a_legend_figure_is_widened_by_the_strip_and_the_axes_stay_left_of_it(tmp_path):
    fig, ax = style.new_figure(legend=True, width=6.0, height=3.0)
    assert tuple(fig.get_size_inches()) == pytest.approx((6.0 + style.LEGEND_WIDTH, 3.0), abs=1e-12)
    ax.plot([0, 1], [0, 1], label="a line with a long label")
    style.legend_outside(fig, ax, title="F_stat")
    path = style.save_figure(fig, tmp_path / "f.png")
    assert path == tmp_path / "f.png" and path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    strip = 1.0 - style.LEGEND_WIDTH / fig.get_figwidth()
    assert ax.get_position().x1 <= strip + 1e-9  # tight_layout kept the strip free of axes
    (legend,) = fig.legends
    assert legend.get_title().get_text() == "F_stat"
    plain, _ = style.new_figure(width=6.0, height=3.0)
    assert tuple(plain.get_size_inches()) == pytest.approx((6.0, 3.0), abs=1e-12)


@pytest.mark.parametrize(("suffix", "magic"), [(".pdf", b"%PDF"), (".svg", b"<?xml")])
def test_the_suffix_selects_the_format(tmp_path, suffix, magic):
    fig, ax = style.new_figure()
    ax.plot([0, 1], [1, 0])
    assert style.save_figure(fig, tmp_path / f"f{suffix}").read_bytes()[:len(magic)] == magic
    assert not hasattr(fig, "number")  # never a pyplot figure: none piles up in long runs
