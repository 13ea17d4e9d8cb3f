"""What a trace written by a command records of the run that made it: the command line,
every option (as parsed, defaults included), the engine, and the input file's name.
Specification: ``specs/trace.md`` (provenance keys)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Mapping
from pathlib import Path

import attrs

from geomexact.trace.record import Trace

JsonValue = None | bool | int | str | list["JsonValue"] | dict[str, "JsonValue"]

_NOT_OPTIONS = frozenset({"run", "argv", "command", "trace_command", "version"})
"""Namespace entries that are the parser's own bookkeeping, not options."""


def command_line(args: argparse.Namespace) -> list[str]:
    """The command line that ran (``["geomexact", "refine", …]``): the arguments
    :func:`geomexact.cli.main` was given, else the process's."""
    argv = getattr(args, "argv", None)
    return list(argv) if argv is not None else ["geomexact", *sys.argv[1:]]


def _json(value: object) -> JsonValue:
    """``value`` as JSON without floats (a trace holds none): numbers other than ints as
    their text, paths as strings, sequences as lists."""
    if value is None or isinstance(value, bool | int | str):
        return value
    if isinstance(value, list | tuple):
        return [_json(item) for item in value]
    if isinstance(value, Mapping):
        return {str(key): _json(item) for key, item in value.items()}
    return str(value)


def options_of(args: argparse.Namespace) -> dict[str, JsonValue]:
    """Every option of the command as parsed (defaults included), by its name."""
    return {name: _json(value) for name, value in sorted(vars(args).items())
            if name not in _NOT_OPTIONS}


def provenance(args: argparse.Namespace, engine: str) -> dict[str, JsonValue]:
    """The parameters a command adds to the traces it writes: ``command`` (the command
    line), ``options`` (:func:`options_of`) and ``engine`` (the engine that ran)."""
    return {"command": _json(command_line(args)), "options": options_of(args), "engine": engine}


def with_provenance(
    trace: Trace, args: argparse.Namespace, *, engine: str, input_path: str | Path | None
) -> Trace:
    """``trace`` with the :func:`provenance` of the run among its parameters and the name
    of its input file (when there is one)."""
    parameters = {**dict(trace.parameters), **provenance(args, engine)}
    name = Path(input_path).name if input_path is not None else trace.input_name
    return attrs.evolve(trace, parameters=parameters, input_name=name)
