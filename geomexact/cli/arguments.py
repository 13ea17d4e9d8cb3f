"""The parts of the argument parser the commands share: adding a command (as
:mod:`~geomexact.cli.command_table` describes it), the common options (``--json``, ``-v``,
``--format``, ``--to``), the arguments and options several commands declare with their own
help text (``INPUT``, ``TRACE``, ``-o``, ``--trace``, ``--check``, ``--picture``,
``--engine``), a table's options that each take one value, and the argument types."""

from __future__ import annotations

import argparse
from collections.abc import Callable, Sequence
from typing import TypeAlias

import attrs

from geomexact import io
from geomexact.cli.command_table import command_spec

Subcommands: TypeAlias = "argparse._SubParsersAction[argparse.ArgumentParser]"
"""What :meth:`argparse.ArgumentParser.add_subparsers` returns: where commands are added."""


def examples_text(examples: Sequence[str]) -> str:
    """``examples:`` and the command lines ``examples``, one a line."""
    lines = "".join(f"  {example}\n" for example in examples)
    return f"examples:\n{lines}"


def command_epilog(examples: Sequence[str]) -> str:
    """The end of a command's ``--help``: its examples (two or three command lines), then
    where the exit codes are (listed once, in ``geomexact --help``)."""
    if not 2 <= len(examples) <= 3:
        raise ValueError(f"a command shows two or three examples, not {len(examples)}")
    return f"{examples_text(examples)}\nexit codes: geomexact help exit-codes\n"


def add_command_parser(commands: Subcommands, path: str,
                       epilog: Callable[[Sequence[str]], str] = command_epilog,
                       ) -> argparse.ArgumentParser:
    """Add the parser of command ``path`` (a name or ``"COMMAND SUBCOMMAND"``) of
    :data:`~geomexact.cli.command_table.COMMAND_TABLE`: its summary is its help line and
    description, ``epilog(examples)`` ends its ``--help``."""
    spec = command_spec(path)
    return commands.add_parser(
        spec.name, help=spec.summary, description=spec.summary,
        epilog=epilog(spec.examples), formatter_class=argparse.RawDescriptionHelpFormatter,
    )


def add_command(commands: Subcommands, path: str,
                run: Callable[[argparse.Namespace], int]) -> argparse.ArgumentParser:
    """Add command ``path`` (:func:`add_command_parser`), running ``run(args)``, with
    ``--max-memory`` unless its table entry says otherwise."""
    sub = add_command_parser(commands, path)
    sub.set_defaults(run=run)
    if command_spec(path).max_memory:
        sub.add_argument("--max-memory", type=memory_size, default=None, metavar="SIZE",
                         help="use at most this much memory, e.g. 512M or 4G (default: 80%% "
                              "of this machine's, within ulimit -v); a command that would "
                              "need more refuses before it starts (exit 2), or stops with "
                              "its partial result (exit 3)")
    return sub


def memory_size(text: str) -> int:
    """``--max-memory``: a size such as ``512M`` or ``4G`` (bytes when plain)."""
    from geomexact.cli.memory import parse_size

    try:
        return parse_size(text)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def add_json_flag(sub: argparse.ArgumentParser) -> None:
    """``--json``: print one JSON object on stdout."""
    sub.add_argument("--json", action="store_true", help="print one JSON object on stdout")


def add_verbose_flag(sub: argparse.ArgumentParser) -> None:
    """``-v``/``--verbose``: print the reader's notes on stderr."""
    sub.add_argument(
        "-v", "--verbose", action="store_true",
        help="print the reader's notes (e.g. orientation fixed) on stderr",
    )


def add_number_flags(sub: argparse.ArgumentParser) -> None:
    """``--exact`` / ``--float``: how numbers are written (``args.numbers``, a
    :data:`~geomexact.io.registry.NumberStyle`; the default ``"decimal"`` is lossless for
    every number with a finite decimal expansion)."""
    group = sub.add_mutually_exclusive_group()
    group.add_argument(
        "--exact", dest="numbers", action="store_const", const="exact", default="decimal",
        help="write numbers without a finite decimal expansion exactly as p/q (by default "
        "every other number is written as its exact decimal, and those are rounded to the "
        "nearest double with a warning)",
    )
    group.add_argument(
        "--float", dest="numbers", action="store_const", const="float",
        help="write every number as the nearest double (warns how many were rounded)",
    )


def add_force_flag(sub: argparse.ArgumentParser, what: str = "existing files") -> None:
    """``--force``: replace ``what`` (nothing is overwritten without it)."""
    sub.add_argument("--force", action="store_true", help=f"replace {what}")


def format_names() -> list[str]:
    """The file format names, sorted: the choices of every format option."""
    return sorted(io.FORMATS)


def add_format_option(sub: argparse.ArgumentParser, help: str | None = None) -> None:
    """``--format F``: the format of the input file (default: by its extension); ``help``,
    when given, replaces the text that says so."""
    names = format_names()
    if help is None:
        help = f"file format, one of {', '.join(names)} (default: from the extension)"
    sub.add_argument("--format", choices=names, metavar="F", help=help)


def add_to_option(sub: argparse.ArgumentParser,
                  help: str = "format of OUT (default: by its extension)") -> None:
    """``--to F``: the format of the output file OUT (default: by its extension)."""
    sub.add_argument("--to", choices=format_names(), metavar="F", help=help)


MESH_OR_PSLG = "triangle mesh (.ele, OFF, …) or a PSLG (triangulated first)"
"""The INPUT of a command that takes a triangle mesh and triangulates a PSLG first."""


def add_input_argument(sub: argparse.ArgumentParser, help: str, *,
                       optional: bool = False) -> None:
    """``INPUT`` (``args.input``): the file the command reads, as ``help`` says; with
    ``optional`` it may be left out (then None)."""
    sub.add_argument("input", metavar="INPUT", nargs="?" if optional else None, help=help)


def add_trace_argument(sub: argparse.ArgumentParser,
                       help: str = "trace file (JSON Lines, or .gz)") -> None:
    """``TRACE`` (``args.trace``): the trace file the command reads."""
    sub.add_argument("trace", metavar="TRACE", help=help)


def add_output_option(sub: argparse.ArgumentParser, help: str = "mesh file to write", *,
                      metavar: str = "OUT", required: bool = False) -> None:
    """``-o``/``--output`` (``args.output``): the file, or folder, the command writes,
    named ``metavar`` in ``--help``; with ``required`` the command needs it."""
    sub.add_argument("-o", "--output", metavar=metavar, required=required, help=help)


def add_trace_output(sub: argparse.ArgumentParser, help: str) -> None:
    """``--trace FILE`` (``args.trace``): write the run's trace to FILE."""
    sub.add_argument("--trace", metavar="FILE", help=help)


def add_check_flag(sub: argparse.ArgumentParser, help: str) -> None:
    """``--check`` (``args.check``): validate the result; ``help`` says what is checked
    and the exit code."""
    sub.add_argument("--check", action="store_true", help=help)


def add_picture_option(sub: argparse.ArgumentParser, help: str, *, metavar: str) -> None:
    """``--picture`` (``args.picture``): draw a picture (.png, .svg or .pdf) to the file
    named ``metavar`` in ``--help``."""
    sub.add_argument("--picture", metavar=metavar, help=help)


def add_engine_option(sub: argparse.ArgumentParser, choices: Sequence[str],
                      help: str) -> None:
    """``--engine`` (``args.engine``): one of ``choices`` (in the order ``--help`` lists
    them), default ``"auto"``."""
    sub.add_argument("--engine", choices=choices, default="auto", help=help)


def add_reading_options(sub: argparse.ArgumentParser, *, force: str | None = None) -> None:
    """The options of a command that reads a file and reports on it: ``--format F``,
    ``--force`` (replace ``force``; for a command that writes files), ``--json`` and
    ``-v``."""
    add_format_option(sub)
    if force is not None:
        add_force_flag(sub, force)
    add_json_flag(sub)
    add_verbose_flag(sub)


def add_writing_options(sub: argparse.ArgumentParser, *, formats: bool = True) -> None:
    """The options of a command that reads a file and writes others: ``--format F`` and
    ``--to F`` (with ``formats``), ``--exact`` / ``--float``, ``--force``, ``--json`` and
    ``-v``."""
    if formats:
        add_format_option(sub)
        add_to_option(sub)
    add_number_flags(sub)
    add_force_flag(sub)
    add_json_flag(sub)
    add_verbose_flag(sub)


@attrs.frozen(slots=True)
class ValueOption:
    """An option that takes one value (a string, None when not given): its ``flag``
    (``--max-area``, also its ``args`` name), the ``metavar`` that names the value in
    ``--help`` and its ``help`` text."""

    flag: str
    metavar: str
    help: str

    def add_to(self, sub: argparse.ArgumentParser | argparse._ArgumentGroup) -> None:
        """Add the option to ``sub``, a parser or an argument group."""
        sub.add_argument(self.flag, metavar=self.metavar, help=self.help)


@attrs.frozen(slots=True)
class ChoiceOption:
    """An option that takes one of ``choices`` (None when not given; ``--help`` lists
    them): its ``flag`` (also its ``args`` name) and its ``help`` text."""

    flag: str
    choices: tuple[str, ...]
    help: str

    def add_to(self, sub: argparse.ArgumentParser | argparse._ArgumentGroup) -> None:
        """Add the option to ``sub``, a parser or an argument group."""
        sub.add_argument(self.flag, choices=self.choices, help=self.help)


def add_options(sub: argparse.ArgumentParser | argparse._ArgumentGroup,
                options: Sequence[ValueOption | ChoiceOption]) -> None:
    """Add each of ``options`` to ``sub`` (a parser or an argument group), in order."""
    for option in options:
        option.add_to(sub)


def non_negative(text: str) -> int:
    """An integer argument >= 0."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"{value} is negative")
    return value


def positive_int(text: str) -> int:
    """An integer argument >= 1."""
    value = non_negative(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"{value} is not >= 1")
    return value


def positive_float(text: str) -> float:
    """A finite number argument > 0."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not value > 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"{text} is not a positive number")
    return value


def add_run_outputs(sub: argparse.ArgumentParser, *, output: str, start: str,
                    trace: str) -> None:
    """The outputs of a command that makes a mesh by recorded steps: ``-o OUT`` (with
    ``--to``), ``--start FILE`` (the trace's input), ``--trace FILE``, ``--exact`` /
    ``--float``, ``--force`` and ``--json``; the texts say what each writes."""
    add_output_option(sub, output)
    add_to_option(sub)
    sub.add_argument("--start", metavar="FILE", help=start)
    add_trace_output(sub, trace)
    add_number_flags(sub)
    add_force_flag(sub, "existing output files")
    add_json_flag(sub)
