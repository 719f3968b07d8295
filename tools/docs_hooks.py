"""MkDocs hooks for the documentation site (``mkdocs.yml``: ``hooks``).

Markers in a page are replaced at build time, so that nothing is written
twice:

- ``<!-- aquagait-readme -->``: the repository's README (the site's front page
  is the README, its ``docs/`` links made relative to the site).
- ``<!-- aquagait-cli -->``: the command line's reference, made from
  ``aquagait.cli.build_parser``: one section per command with its usage, what
  it does and a table of its arguments.
- ``<!-- aquagait-gallery -->``: a section per library creature with its
  picture (``docs/gallery/NAME.png``) and its rows of the library page's two
  tables (``docs/library.md``: what it is, and how it swims).
"""

from __future__ import annotations

import argparse
from pathlib import Path

README, CLI, GALLERY = (
    "<!-- aquagait-readme -->",
    "<!-- aquagait-cli -->",
    "<!-- aquagait-gallery -->",
)


def on_page_markdown(markdown: str, page, config, files) -> str:
    """Put the README, the CLI reference and the gallery where a page asks for them."""
    if README in markdown:
        readme = (Path(config["config_file_path"]).parent / "README.md").read_text()
        markdown = markdown.replace(README, readme.replace("](docs/", "]("))
    if CLI in markdown:
        from aquagait.cli import build_parser

        markdown = markdown.replace(CLI, cli_reference(build_parser()))
    if GALLERY in markdown:
        library = (Path(config["docs_dir"]) / "library.md").read_text()
        markdown = markdown.replace(GALLERY, gallery(library))
    return markdown


def gallery(library: str) -> str:
    """Markdown: for each creature of the library page's first table, its picture and its
    row of every table on that page whose first column names creatures."""
    tables = [t for t in _tables(library) if t[0][0].strip() == "creature"]
    if not tables:
        raise ValueError("docs/library.md has no table whose first column is 'creature'")
    sections = []
    for row in tables[0][2:]:
        name = row[0].strip().strip("`")
        parts = [f"## {name}", f"![{name} swimming, its wake drawn](gallery/{name}.png)"]
        for header, rule, *rows in tables:
            mine = [r for r in rows if r[0].strip().strip("`") == name]
            if mine:
                parts.append("\n".join("|" + "|".join(r) + "|" for r in (header, rule, mine[0])))
        sections.append("\n\n".join(parts))
    return "\n\n".join(sections)


def _tables(markdown: str) -> list[list[list[str]]]:
    """The Markdown tables of a page, each a list of rows of cells (header and rule first)."""
    tables, current = [], []
    for line in markdown.splitlines():
        if line.startswith("|") and line.rstrip().endswith("|"):
            current.append(line.strip()[1:-1].split("|"))
        elif current:
            tables.append(current)
            current = []
    return tables + ([current] if current else [])


def cli_reference(parser: argparse.ArgumentParser) -> str:
    """Markdown for the parser's commands: a section each, in the parser's order."""
    sections = [_usage(parser), _arguments(parser)]
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            helps = {choice.dest: choice.help for choice in action._choices_actions}
            for name, command in action.choices.items():
                sections += [
                    f"## aquagait {name}\n\n{_sentence(helps.get(name, ''))}",
                    _usage(command),
                    _arguments(command),
                ]
    return "\n\n".join(section for section in sections if section)


def _usage(parser: argparse.ArgumentParser) -> str:
    usage = parser.format_usage().removeprefix("usage: ").strip()
    return f"```text\n{usage}\n```"


def _arguments(parser: argparse.ArgumentParser) -> str:
    rows = []
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction | argparse._HelpAction):
            continue
        name = (
            ", ".join(f"`{s}`" for s in action.option_strings)
            or f"`{action.metavar or action.dest}`"
        )
        if action.option_strings and action.nargs != 0:
            name += f" `{_metavar(action)}`"
        rows.append(f"| {name} | {_describe(action)} |")
    if not rows:
        return ""
    return "| argument | meaning |\n|---|---|\n" + "\n".join(rows)


def _metavar(action: argparse.Action) -> str:
    if action.metavar is not None:
        metavar = action.metavar if isinstance(action.metavar, str) else " ".join(action.metavar)
    elif action.choices is not None:
        metavar = "{" + ",".join(map(str, action.choices)) + "}"
    else:
        metavar = action.dest.upper()
    return f"{metavar} ..." if action.nargs in ("+", "*") else metavar


def _describe(action: argparse.Action) -> str:
    text = _sentence(action.help or "")
    if action.choices is not None and not action.option_strings:
        text += f" One of: {', '.join(f'`{c}`' for c in action.choices)}."
    default = action.default
    if action.option_strings and action.nargs != 0 and default not in (None, argparse.SUPPRESS):
        text += f" Default: `{default}`."
    return text.replace("|", "\\|").replace("\n", " ")


def _sentence(text: str) -> str:
    text = " ".join(text.split()).replace("%%", "%")  # argparse's escape
    return f"{text[:1].upper()}{text[1:]}." if text and not text.endswith(".") else text
