"""How a result shows itself in a notebook, and gives its tables as data frames.

A result builds its table once, as rows of column -> value with the unit in each column's name
(``S [mm]``); :func:`html_summary` renders the headline, the lines under it and that table for
Jupyter (``_repr_html_``), and :func:`data_frame` hands the same rows to pandas (``to_frame``).
pandas is a dependency of xarray, and so of every install; it is imported only when a frame is asked for.
"""

from __future__ import annotations

import html
import math
from collections.abc import Mapping, Sequence

Rows = Sequence[Mapping[str, object]]


def data_frame(rows: Rows):
    """The rows as a pandas DataFrame, one column per key of the first row.

    Parameters
    ----------
    rows : sequence of mapping
        One mapping of column name (with its unit) to value per row.

    Examples
    --------
    >>> from presag_opt.display import data_frame
    >>> frame = data_frame([{"method": "Δe rule", "S [mm]": 60.8}, {"method": "robust", "S [mm]": 55.8}])
    >>> frame.columns.tolist(), frame["S [mm]"].tolist()
    (['method', 'S [mm]'], [60.8, 55.8])
    """
    import pandas as pd

    return pd.DataFrame(list(rows), columns=list(rows[0]) if rows else None)


def _cell(value: object) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "–"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        return f"{value:.4g}" if abs(value) < 1 else f"{value:.1f}"
    return html.escape(str(value))


def html_table(rows: Rows) -> str:
    """The rows as an HTML table (numbers to 4 significant digits below 1, else to 0.1).

    Parameters
    ----------
    rows : sequence of mapping
        One mapping of column name to value per row.
    """
    if not rows:
        return ""
    columns = list(rows[0])
    head = "".join(f"<th>{html.escape(c)}</th>" for c in columns)
    body = "".join("<tr>" + "".join(f"<td>{_cell(r.get(c))}</td>" for c in columns) + "</tr>" for r in rows)
    return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def html_summary(headline: str, lines: Sequence[str] = (), rows: Rows = ()) -> str:
    """A result in a notebook: its headline in bold, the lines under it, its key table.

    Parameters
    ----------
    headline : str
        One line: the answer.
    lines : sequence of str
        Why, margins, what was not checked (leading spaces and a ``name:`` prefix are kept as text).
    rows : sequence of mapping
        The key table.

    Examples
    --------
    >>> from presag_opt.display import html_summary
    >>> html_summary("Pre-sag to build: 56 mm", ["why: the Δe rule"], [{"S [mm]": 55.9}])
    '<div><p><strong>Pre-sag to build: 56 mm</strong></p><ul><li>why: the Δe rule</li></ul><table>...</table></div>'
    """
    items = "".join(f"<li>{html.escape(line.strip())}</li>" for line in lines)
    return (f"<div><p><strong>{html.escape(headline)}</strong></p>" + (f"<ul>{items}</ul>" if items else "")
            + html_table(rows) + "</div>")
