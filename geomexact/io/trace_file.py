"""The trace file format: UTF-8 JSON Lines.

Line 1 is the header
``{"format": "geomexact-trace", "version": 1, "geomexact": "...", "input_digest": "<hex>",
"parameters": {...}, "steps": n}``; each further line is one step
``{"i": k, "op": "flip", "args": [3, 5, "1/2"], "digest": "<hex>"}`` where integer
arguments are vertex ids and string arguments are exact rationals ``"p/q"``.  Keys are
sorted and separators fixed, so the same run gives byte-identical files on every machine.
Specification: ``specs/trace.md``.
"""

from __future__ import annotations

import json
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

from geomexact.errors import FormatError
from geomexact.io.files import read_text, write_lines_atomic
from geomexact.kernel.numbers import Rational, parse_rational
from geomexact.trace.record import Trace
from geomexact.trace.step import Step, StepArgument

FORMAT_NAME = "geomexact-trace"
FORMAT_VERSION = 1


def _argument_json(value: StepArgument) -> int | str:
    if isinstance(value, int):
        return value
    return f"{value.numerator}/{value.denominator}"


def _dumps(record: Mapping[str, Any]) -> str:
    return json.dumps(record, sort_keys=True, separators=(",", ":"), ensure_ascii=True)


def trace_lines(trace: Trace) -> Iterator[str]:
    """The lines of the trace file (without newlines)."""
    yield _dumps(
        {
            "format": FORMAT_NAME,
            "version": FORMAT_VERSION,
            "geomexact": trace.version,
            "input_digest": f"{trace.input_digest:032x}",
            "parameters": dict(trace.parameters),
            "steps": len(trace.steps),
        }
    )
    for index, (step, digest) in enumerate(zip(trace.steps, trace.digests, strict=True)):
        yield _dumps(
            {
                "i": index + 1,
                "op": step.op,
                "args": [_argument_json(a) for a in step.args],
                "digest": f"{digest:032x}",
            }
        )


def trace_text(trace: Trace) -> str:
    """The whole trace file as text."""
    return "".join(line + "\n" for line in trace_lines(trace))


def parse_trace(text: str, path: str = "<trace>") -> Trace:
    """Read a trace file's text; raises :class:`FormatError` naming the line and problem."""
    lines = text.splitlines()
    if not lines:
        raise FormatError(path, None, "empty trace file")
    header = _json_line(lines[0], path, 1)
    if header.get("format") != FORMAT_NAME:
        raise FormatError(path, 1, f"not a geomexact trace (format is {header.get('format')!r})")
    if header.get("version") != FORMAT_VERSION:
        raise FormatError(path, 1, f"unsupported trace version {header.get('version')!r}")
    input_digest = _hex(header.get("input_digest"), path, 1)
    parameters = header.get("parameters", {})
    if not isinstance(parameters, dict):
        raise FormatError(path, 1, "parameters must be a JSON object")
    steps: list[Step] = []
    digests: list[int] = []
    for number, line in enumerate(lines[1:], start=2):
        if not line.strip():
            continue
        record = _json_line(line, path, number)
        if record.get("i") != len(steps) + 1:
            raise FormatError(path, number, f"expected step number {len(steps) + 1}, "
                              f"found {record.get('i')!r}")
        op, args = record.get("op"), record.get("args")
        if not isinstance(op, str) or not isinstance(args, list):
            raise FormatError(path, number, "a step needs a string 'op' and a list 'args'")
        steps.append(Step(op, tuple(_argument(a, path, number) for a in args)))
        digests.append(_hex(record.get("digest"), path, number))
    expected = header.get("steps")
    if expected is not None and expected != len(steps):
        raise FormatError(path, len(lines), f"truncated trace: the header announces "
                          f"{expected} steps, the file has {len(steps)}")
    return Trace(input_digest, steps, digests, parameters, str(header.get("geomexact", "")))


def _json_line(line: str, path: str, number: int) -> dict[str, Any]:
    try:
        record = json.loads(line)
    except json.JSONDecodeError as error:
        raise FormatError(path, number, f"not valid JSON ({error.msg})") from error
    if not isinstance(record, dict):
        raise FormatError(path, number, "each line must be a JSON object")
    return record


def _hex(value: object, path: str, number: int) -> int:
    if not isinstance(value, str) or len(value) != 32:
        raise FormatError(path, number, f"a digest must be 32 hexadecimal digits, got {value!r}")
    try:
        return int(value, 16)
    except ValueError as error:
        raise FormatError(path, number, f"bad digest {value!r}") from error


def _argument(value: object, path: str, number: int) -> int | Rational:
    if isinstance(value, bool) or not isinstance(value, int | str):
        raise FormatError(path, number, f"step argument {value!r} is neither a vertex id "
                          "nor a rational 'p/q'")
    if isinstance(value, int):
        return value
    try:
        return parse_rational(value)
    except ValueError as error:
        raise FormatError(path, number, str(error)) from error


def write_trace(path: str | Path, trace: Trace, *, overwrite: bool = False) -> None:
    """Write ``trace`` to ``path`` atomically, line by line (a long trace is never held in
    memory as text); refuses to replace a file unless ``overwrite``."""
    write_lines_atomic(path, trace_lines(trace), overwrite=overwrite)


def read_trace(path: str | Path) -> Trace:
    """Read a trace file (see :func:`parse_trace`)."""
    return parse_trace(read_text(path), str(path))

