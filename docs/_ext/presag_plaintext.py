"""The docstrings' plain-text conventions, read as the authors meant them.

The docstrings write absolute values and norms the way one does in plain text, ``|x|`` or
``|uplift / expected − 1|``; reStructuredText reads ``|name|`` as a substitution and fails. On
autodoc's ``process-docstring`` event, a pair of bars around text on one line (not at the start of
a line, where a table or line block would begin, and not inside double backquotes) is escaped, so
it renders as written. Nothing else in a docstring is changed.
"""

from __future__ import annotations

import re

BARS = re.compile(r"(?<![\\`|\w])\|(?=[^\s|])([^|`\n]*?[^\s|\\])\|(?![\w`|])")
LITERAL = re.compile(r"``.*?``")


def _escape(line: str) -> str:
    if line.lstrip().startswith(("|", "+")):
        return line
    pieces, last = [], 0
    for match in LITERAL.finditer(line):
        pieces.append(BARS.sub(r"\\|\1\\|", line[last:match.start()]))
        pieces.append(match.group(0))
        last = match.end()
    pieces.append(BARS.sub(r"\\|\1\\|", line[last:]))
    return "".join(pieces)


def escape_bars(app, what, name, obj, options, lines: list[str]) -> None:
    lines[:] = [_escape(line) for line in lines]


def setup(app) -> dict:
    app.connect("autodoc-process-docstring", escape_bars, priority=400)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
