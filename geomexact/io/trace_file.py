"""The trace file format: UTF-8 JSON Lines.

Line 1 is the header
``{"format": "geomexact-trace", "version": 1, "geomexact": "...", "input_digest": "<hex>",
"parameters": {...}, "steps": n, "header_digest": "<hex>"}`` (and ``"input_name"``, the
input's file name, when the run knows it; ``header_digest`` covers the other fields, and a
header without it, written before it existed, reads unchecked); each further line is one
step
``{"i": k, "op": "flip", "args": [3, 5, "1/2"], "digest": "<hex>"}`` where integer
arguments are vertex ids and string arguments are exact rationals ``"p/q"``.  Keys are
sorted and separators fixed, so the same run gives byte-identical files on every machine.
A file may be gzip-compressed (written so when its name ends in ``.gz``; read so when it
starts with the gzip magic bytes).  Specification: ``specs/trace.md``.
"""

from __future__ import annotations

import hashlib
import json
import re
from collections.abc import Iterable, Iterator, Mapping
from pathlib import Path
from typing import Any

from geomexact.errors import FormatError
from geomexact.io.files import read_lines, write_lines_atomic
from geomexact.io.registry import bounded, clipped, parse_number, quoted
from geomexact.kernel.numbers import Rational
from geomexact.trace.record import Trace
from geomexact.trace.step import Step, StepArgument

FORMAT_NAME = "geomexact-trace"
FORMAT_VERSION = 1
HEADER_DIGEST = "header_digest"
"""The header field that holds :func:`header_digest` of the header's other fields."""


def _argument_json(value: StepArgument) -> int | str:
    if isinstance(value, int):
        return value
    return f"{value.numerator}/{value.denominator}"


def _dumps(record: Mapping[str, Any]) -> str:
    return json.dumps(record, sort_keys=True, separators=(",", ":"), ensure_ascii=True)


def header_digest(fields: Mapping[str, Any]) -> str:
    """The BLAKE2b-128 digest (32 hex digits) of a trace header's ``fields`` (every field
    but ``header_digest``) in their canonical JSON: an edit of the header shows, however
    the line is then formatted.  It detects changes, it does not sign: anyone may
    compute it."""
    canonical = _dumps({k: v for k, v in fields.items() if k != HEADER_DIGEST})
    return hashlib.blake2b(canonical.encode("ascii"), digest_size=16,
                           person=b"trace-header").hexdigest()


def trace_lines(trace: Trace) -> Iterator[str]:
    """The lines of the trace file (without newlines)."""
    header: dict[str, Any] = {
        "format": FORMAT_NAME,
        "version": FORMAT_VERSION,
        "geomexact": trace.version,
        "input_digest": f"{trace.input_digest:032x}",
        "parameters": dict(trace.parameters),
        "steps": len(trace.steps),
    }
    if trace.input_name:  # only when known: traces without it keep their old bytes
        header["input_name"] = trace.input_name
    header[HEADER_DIGEST] = header_digest(header)
    yield _dumps(header)
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
    """Read a trace file's text; raises :class:`FormatError` naming the line and problem.
    Lines are split on ``\\n`` (as :func:`read_trace` splits a file)."""
    try:
        return _parse_lines(enumerate(text.removeprefix("\ufeff").split("\n"), start=1), path)
    except FormatError as error:
        raise bounded(error) from error.__cause__


def _parse_lines(lines: Iterable[tuple[int, str]], path: str) -> Trace:
    rows = (row for row in lines if row[1].strip())
    first = next(rows, None)
    if first is None:
        raise FormatError(path, None, "empty trace file")
    number, line = first
    header = _json_line(line, path, number)
    if header.get("format") != FORMAT_NAME:
        raise FormatError(
            path, number, f"not a geomexact trace (format is {_shown(header.get('format'))})"
        )
    if header.get("version") != FORMAT_VERSION:
        raise FormatError(
            path, number, f"unsupported trace version {_shown(header.get('version'))}"
        )
    input_digest = _hex(header.get("input_digest"), path, number)
    parameters = header.get("parameters", {})
    if not isinstance(parameters, dict):
        raise FormatError(path, number, "parameters must be a JSON object")
    input_name = header.get("input_name", "")
    if not isinstance(input_name, str):
        raise FormatError(path, number, "input_name must be a JSON string")
    expected = header.get("steps")
    if expected is not None and (isinstance(expected, bool) or not isinstance(expected, int)
                                 or expected < 0):
        raise FormatError(path, number, f"steps must be a count, not {_shown(expected)}")
    version = header.get("geomexact", "")
    if not isinstance(version, str):
        raise FormatError(path, number, "geomexact (the version) must be a JSON string")
    _check_header_digest(header, path, number)
    steps: list[Step] = []
    digests: list[int] = []
    last = number
    for number, line in rows:
        last = number
        record = _json_line(line, path, number)
        if record.get("i") != len(steps) + 1:
            raise FormatError(path, number, f"expected step number {len(steps) + 1}, "
                              f"found {_shown(record.get('i'))}")
        op, args = record.get("op"), record.get("args")
        if not isinstance(op, str) or not isinstance(args, list):
            raise FormatError(path, number, "a step needs a string 'op' and a list 'args'")
        steps.append(Step(op, tuple(_argument(a, path, number) for a in args)))
        digests.append(_hex(record.get("digest"), path, number))
    if expected is not None and expected != len(steps):
        raise FormatError(path, last, f"truncated trace: the header announces "
                          f"{expected} steps, the file has {len(steps)}")
    return Trace(input_digest, steps, digests, parameters, version, input_name)


def _check_header_digest(header: Mapping[str, Any], path: str, number: int) -> None:
    """A :class:`FormatError` when the header's ``header_digest`` is not that of its other
    fields (a header without one, written before it existed, is not checked)."""
    if HEADER_DIGEST not in header:
        return
    recorded = header[HEADER_DIGEST]
    if not isinstance(recorded, str) or not _HEX.fullmatch(recorded):
        raise FormatError(path, number, f"header_digest must be 32 hexadecimal digits, got "
                          f"{_shown(recorded)}")
    if recorded.lower() != header_digest(header):
        raise FormatError(path, number, "the header was changed after the trace was written "
                          "(its header_digest does not match its fields)")


def _shown(value: object) -> str:
    """A JSON value for a message, at most about 200 characters of it."""
    return quoted(value) if isinstance(value, str) else clipped(repr(value))


def _json_line(line: str, path: str, number: int) -> dict[str, Any]:
    try:
        record = json.loads(line)
    except json.JSONDecodeError as error:
        raise FormatError(path, number, f"not valid JSON ({error.msg})") from error
    except RecursionError as error:
        raise FormatError(path, number, "not valid JSON here (nested too deeply)") from error
    except ValueError as error:  # e.g. an integer of more digits than int() converts
        raise FormatError(path, number, f"not valid JSON here ({clipped(str(error))})") from error
    if not isinstance(record, dict):
        raise FormatError(path, number, "each line must be a JSON object")
    return record


_HEX = re.compile(r"[0-9a-fA-F]{32}")


def _hex(value: object, path: str, number: int) -> int:
    if not isinstance(value, str) or not _HEX.fullmatch(value):
        raise FormatError(
            path, number, f"a digest must be 32 hexadecimal digits, got {_shown(value)}"
        )
    return int(value, 16)


def _argument(value: object, path: str, number: int) -> int | Rational:
    if isinstance(value, bool) or not isinstance(value, int | str):
        raise FormatError(path, number, f"step argument {_shown(value)} is neither a vertex "
                          "id nor a rational 'p/q'")
    if isinstance(value, int):
        return value
    return parse_number(path, number, value, "step argument")


def is_compressed_name(path: str | Path) -> bool:
    """True when ``path`` names a gzip-compressed trace (it ends in ``.gz``)."""
    return Path(path).name.lower().endswith(".gz")


def write_trace(path: str | Path, trace: Trace, *, overwrite: bool = False) -> None:
    """Write ``trace`` to ``path`` atomically, line by line (a long trace is never held in
    memory as text); refuses to replace a file unless ``overwrite``.  A path ending in
    ``.gz`` (``run.trace.jsonl.gz``) is written gzip-compressed, with no time stamp or
    file name in it: the same trace gives the same bytes."""
    write_lines_atomic(path, trace_lines(trace), overwrite=overwrite,
                       compress=is_compressed_name(path))


def read_trace_header(path: str | Path) -> dict[str, Any]:
    """The header of the trace file ``path``: the JSON object of its first line, read
    alone and not checked (:func:`read_trace` checks a whole trace)."""
    for number, line in read_lines(path, decompress=True):
        if line.strip():
            return _json_line(line, str(path), number)
    raise FormatError(str(path), None, "empty trace file")


def read_trace(path: str | Path) -> Trace:
    """Read a trace file (see :func:`parse_trace`), line by line; a gzip-compressed one
    (recognised by its first bytes, whatever its name) is decompressed as it is read."""
    try:
        return _parse_lines(read_lines(path, decompress=True), str(path))
    except FormatError as error:
        raise bounded(error) from error.__cause__

