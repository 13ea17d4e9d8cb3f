"""``geomexact help [TOPIC]``: the documentation a pip user has, from the installed
package itself -- a command's full help, the list of commands, the file formats, the exit
codes, and Triangle's switches with the options that replace them."""

from __future__ import annotations

import argparse
import difflib
import textwrap

from geomexact.cli.arguments import Subcommands, add_command_parser, examples_text
from geomexact.cli.command_table import COMMAND_TABLE
from geomexact.cli.errors import UsageProblem
from geomexact.cli.exit_codes import EXIT_CODES_HELP, EXIT_OK
from geomexact.cli.parser import TRIANGLE_SWITCHES, build_parser

TOPICS: tuple[tuple[str, str], ...] = (
    ("commands", "every command with its one-line summary"),
    ("formats", "the file formats, their extensions and what each holds"),
    ("exit-codes", "what each exit status means"),
    ("triangle", "Triangle's switches (-pq30a0.01) and the options that replace them"),
)
"""The topics besides the commands (a command's topic is its ``--help``)."""


def _commands() -> str:
    width = max(len(spec.name) for spec in COMMAND_TABLE)
    rows = [textwrap.fill(spec.summary, 88, initial_indent=f"  {spec.name:<{width}}  ",
                          subsequent_indent=" " * (width + 4))
            for spec in COMMAND_TABLE]
    return "commands (geomexact help COMMAND for one):\n" + "\n".join(rows) + "\n"


def _formats() -> str:
    from geomexact import io

    rows = []
    for name, chosen in sorted(io.FORMATS.items()):
        extensions = ", ".join(chosen.extensions) or "(by --to/--format only)"
        kinds = ", ".join(kind.__name__ for kind in chosen.kinds)
        rows.append(f"  {name}: {extensions} -- {kinds}\n" + textwrap.fill(
            chosen.description, 88, initial_indent="      ", subsequent_indent="      "))
    return ("file formats (chosen by the extension; --format/--from/--to name one):\n"
            + "\n".join(rows) + "\n")


def _triangle() -> str:
    rows = [f"  -{letter}  {meaning}" for letter, meaning in TRIANGLE_SWITCHES.items()]
    return ("Triangle's switches and what geomexact does instead\n(-pq30a0.01 is "
            "'geomexact refine IN.poly --min-angle 30 --max-area 0.01 -o OUT'):\n"
            + "\n".join(rows) + "\n")


def _command_help(name: str) -> str:
    parser = build_parser([name])
    for action in parser._actions:  # argparse keeps its subparsers only here
        if isinstance(action, argparse._SubParsersAction):
            return str(action.choices[name].format_help())
    raise AssertionError("the parser has no commands")  # pragma: no cover


def help_text(topic: str | None) -> str:
    """The text of ``topic`` (None: the list of topics); :class:`UsageProblem` naming
    the closest topic for an unknown one."""
    commands = [spec.name for spec in COMMAND_TABLE]
    if topic is None:
        width = max(len(name) for name, _ in TOPICS)
        rows = [f"  {name:<{width}}  {what}" for name, what in TOPICS]
        return ("geomexact help TOPIC, where TOPIC is a command (geomexact help refine) or "
                "one of:\n" + "\n".join(rows) + "\n\n" + _commands())
    if topic in commands:
        return _command_help(topic)
    shown = {"commands": _commands, "formats": _formats, "exit-codes": lambda: EXIT_CODES_HELP,
             "triangle": _triangle}
    if topic in shown:
        return shown[topic]()
    known = commands + [name for name, _ in TOPICS]
    close = difflib.get_close_matches(topic, known, n=1)
    hint = f" (did you mean {close[0]!r}?)" if close else ""
    raise UsageProblem(f"no help topic {topic!r}{hint}; topics: {', '.join(known)}")


def command_help(args: argparse.Namespace) -> int:
    """Print the help of ``args.topic``."""
    print(help_text(args.topic), end="")
    return EXIT_OK


def add_parser(commands: Subcommands) -> None:
    """Add the ``help`` command."""
    help_ = add_command_parser(commands, "help", epilog=examples_text)
    help_.set_defaults(run=command_help)
    help_.add_argument("topic", nargs="?", metavar="TOPIC",
                       help="a command or a topic (omit it for the list)")
