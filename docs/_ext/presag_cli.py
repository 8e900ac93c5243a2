"""The command-line reference, written from the live argument parser at build time.

``.. presag-cli::`` renders every sub-command that :func:`presag_opt.cli.build_parser` registers: its
usage line, description, and a table of every option with its metavar, default and help text. A verb
added to the parser (one registration line in ``presag_opt/cli/__init__.py``) appears in the
reference without an edit to the documentation. :func:`commands` is the same walk as plain data, for
the tests.
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass

from docutils import nodes
from sphinx.util.docutils import SphinxDirective


@dataclass(frozen=True, kw_only=True)
class Option:
    """One argument of a command: how it is written, its metavar, default and expanded help."""

    names: str
    metavar: str
    default: str
    help: str


@dataclass(frozen=True, kw_only=True)
class Command:
    """One ``presag`` verb."""

    name: str
    usage: str
    help: str
    description: str
    epilog: str
    options: tuple[Option, ...]


def _parser() -> argparse.ArgumentParser:
    from presag_opt.cli import build_parser

    return build_parser()


def _subparsers(parser: argparse.ArgumentParser) -> argparse._SubParsersAction:
    return next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))


def _options(parser: argparse.ArgumentParser) -> tuple[Option, ...]:
    formatter = parser._get_formatter()
    out = []
    for action in parser._actions:
        if action.help == argparse.SUPPRESS or isinstance(action, argparse._SubParsersAction):
            continue
        names = ", ".join(action.option_strings) or action.dest
        if action.nargs == 0:
            metavar = ""
        elif action.option_strings:
            metavar = formatter._format_args(action, action.dest.upper())
        else:
            metavar = formatter._format_args(action, action.dest)
        default = action.default
        shown = "" if default in (None, False, argparse.SUPPRESS) or action.nargs == 0 else str(default)
        out.append(Option(names=names, metavar=metavar, default=shown,
                          help=formatter._expand_help(action) if action.help else ""))
    return tuple(out)


def commands() -> list[Command]:
    """Every sub-command of ``presag`` with its options, in the order of registration."""
    parser = _parser()
    sub = _subparsers(parser)
    helps = {choice.dest: choice.help or "" for choice in sub._choices_actions}
    out = [Command(name="presag", usage=parser.format_usage().strip(), help=parser.description or "",
                   description=parser.description or "", epilog=parser.epilog or "", options=_options(parser))]
    for name, command in sub.choices.items():
        out.append(Command(name=f"presag {name}", usage=command.format_usage().strip(), help=helps.get(name, ""),
                           description=command.description or "", epilog=command.epilog or "",
                           options=_options(command)))
    return out


def _table(options: tuple[Option, ...]) -> nodes.table:
    table = nodes.table(classes=["cli-options"])
    group = nodes.tgroup(cols=3)
    table += group
    for width in (28, 14, 58):
        group += nodes.colspec(colwidth=width)
    head = nodes.thead()
    group += head
    row = nodes.row()
    for title in ("option", "default", "meaning"):
        row += nodes.entry("", nodes.paragraph(text=title))
    head += row
    body = nodes.tbody()
    group += body
    for option in options:
        row = nodes.row()
        written = f"{option.names} {option.metavar}".strip()
        row += nodes.entry("", nodes.paragraph("", "", nodes.literal(text=written)))
        row += nodes.entry("", nodes.paragraph("", "", nodes.literal(text=option.default)) if option.default
                           else nodes.paragraph(text=""))
        row += nodes.entry("", nodes.paragraph(text=option.help))
        body += row
    return table


class PresagCli(SphinxDirective):
    """``.. presag-cli::``: one section per command, from the parser of the installed package."""

    has_content = False

    def run(self) -> list[nodes.Node]:
        self.env.note_dependency(__file__)
        out = []
        for command in commands():
            section = nodes.section(ids=[nodes.make_id(command.name)], names=[nodes.fully_normalize_name(command.name)])
            section += nodes.title(text=command.name)
            if command.help and command.help != command.description:
                section += nodes.paragraph("", "", nodes.emphasis(text=command.help))
            section += nodes.literal_block(text=command.usage, language="text")
            for paragraph in (p for p in command.description.split("\n\n") if p.strip()):
                section += nodes.paragraph(text=" ".join(paragraph.split()))
            if command.epilog:
                section += nodes.literal_block(text=command.epilog.strip("\n"), language="text")
            if command.options:
                section += _table(command.options)
            self.state.document.note_implicit_target(section)
            out.append(section)
        return out


def setup(app) -> dict:
    app.add_directive("presag-cli", PresagCli)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
