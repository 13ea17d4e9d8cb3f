"""Write the CLI reference of the documentation site from the real ``--help`` texts.

The documentation build calls :func:`write_reference` (``docs/_site_tools.py``, at
``builder-inited``), which writes ``docs/_generated/cli-help.md``: ``geomexact --help``
and then ``geomexact COMMAND --help`` of every command and subcommand, in the order of
:data:`geomexact.cli.parser.COMMANDS`, each formatted at a fixed width so that the page
does not depend on the terminal.  ``tests/package/test_docs_site.py`` checks that every
command of the parser is in the reference and in ``docs/cli.md``.

Usage::

    .venv/bin/python docs/cli_reference.py [--out docs/_generated/cli-help.md]
"""

from __future__ import annotations

import argparse
import os
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

WIDTH = 100
"""The width of the help texts (argparse reads ``COLUMNS``)."""


def _subcommands(parser: argparse.ArgumentParser) -> list[tuple[str, argparse.ArgumentParser]]:
    """The parser's subcommands by name (each parser once, aliases left out), in order."""
    found: list[tuple[str, argparse.ArgumentParser]] = []
    seen: set[int] = set()
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                if id(sub) not in seen:
                    seen.add(id(sub))
                    found.append((name, sub))
    return found


def commands(parser: argparse.ArgumentParser | None = None,
             prefix: tuple[str, ...] = ()) -> list[tuple[tuple[str, ...],
                                                         argparse.ArgumentParser]]:
    """Every command and subcommand of ``geomexact`` as (words, parser): ``("info",)``,
    ``("trace",)``, ``("trace", "show")``, …, depth first in the parser's order."""
    if parser is None:
        from geomexact.cli.parser import build_parser

        parser = build_parser()
    found = []
    for name, sub in _subcommands(parser):
        words = (*prefix, name)
        found.append((words, sub))
        found.extend(commands(sub, words))
    return found


@contextmanager
def _columns(width: int) -> Iterator[None]:
    before = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = str(width)
    try:
        yield
    finally:
        if before is None:
            del os.environ["COLUMNS"]
        else:
            os.environ["COLUMNS"] = before


def anchor(words: tuple[str, ...]) -> str:
    """The heading id of a command's section (``geomexact-trace-show``, the slug that
    myst-parser gives its heading)."""
    return "-".join(("geomexact", *words))


def reference() -> str:
    """The Markdown of the reference page."""
    from geomexact.cli.parser import build_parser

    parser = build_parser()
    with _columns(WIDTH):
        top = parser.format_help()
        sections = [(words, sub.format_help()) for words, sub in commands(parser)]
    lines = [
        "# Command-line reference (generated)",
        "",
        "This page is generated at each build of the site from the real `--help` texts",
        "(`docs/cli_reference.py`, formatted at 100 columns): it cannot fall behind the",
        "program.  The explanations, exit codes and JSON keys are in",
        "[the `geomexact` command](../cli.md).",
        "",
        "| command | |",
        "|---|---|",
    ]
    for words, sub in commands(parser):
        summary = (sub.description or "").strip().splitlines()
        lines.append(f"| [`geomexact {' '.join(words)}`](#{anchor(words)}) | "
                     f"{summary[0] if summary else ''} |")
    lines += ["", "## `geomexact`", "", "```text", top.rstrip(), "```", ""]
    for words, text in sections:
        level = "#" * (len(words) + 1)
        lines += [f"{level} `geomexact {' '.join(words)}`", "",
                  "```text", text.rstrip(), "```", ""]
    return "\n".join(lines)


def write_reference(path: Path) -> bool:
    """Write the reference to ``path`` unless it already holds it; return whether it
    was written."""
    text = reference()
    path.parent.mkdir(parents=True, exist_ok=True)
    if path.exists() and path.read_text(encoding="utf-8") == text:
        return False
    path.write_text(text, encoding="utf-8")
    return True


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path,
                        default=Path(__file__).parent / "_generated" / "cli-help.md")
    args = parser.parse_args()
    write_reference(args.out)
    print(args.out)


if __name__ == "__main__":
    main()
