"""Traces: the record of a run (its steps and the digest after each), their JSON-Lines
files, :func:`replay` and :func:`first_divergence`.

A trace file is UTF-8 JSON Lines.  Line 1 is the header
``{"format": "geomexact-trace", "version": 1, "geomexact": "...", "input_digest": "<hex>",
"parameters": {...}}``; each further line is one step
``{"i": k, "op": "flip", "args": [3, 5, "1/2"], "digest": "<hex>"}`` where integer
arguments are vertex ids and string arguments are exact rationals ``"p/q"``.  Keys are
sorted and separators fixed, so the same run gives byte-identical files on every machine.
Specification: ``specs/trace.md``.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Iterator, Mapping
from pathlib import Path
from typing import Any

import attrs

from geomexact.errors import FormatError, TraceError
from geomexact.kernel.numbers import Rational, parse_rational
from geomexact.mesh2d.ops import apply_in
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh2d.transient import Transient2
from geomexact.trace.step import Step, StepArgument

FORMAT_NAME = "geomexact-trace"
FORMAT_VERSION = 1


def _steps(values: Iterable[Step]) -> tuple[Step, ...]:
    return tuple(values)


def _digests(values: Iterable[int]) -> tuple[int, ...]:
    return tuple(values)


def _freeze(parameters: Mapping[str, Any] | None) -> tuple[tuple[str, Any], ...]:
    return tuple(sorted((parameters or {}).items()))


@attrs.frozen(slots=True)
class Trace:
    """A run: the digest of the mesh it started from, its parameters (JSON values), its
    steps and the mesh digest after each step (``len(digests) == len(steps)``)."""

    input_digest: int
    steps: tuple[Step, ...] = attrs.field(converter=_steps)
    digests: tuple[int, ...] = attrs.field(converter=_digests)
    parameters: tuple[tuple[str, Any], ...] = attrs.field(default=(), converter=_freeze)
    version: str = ""

    def __attrs_post_init__(self) -> None:
        if len(self.steps) != len(self.digests):
            raise ValueError(
                f"a trace needs one digest per step ({len(self.steps)} steps, "
                f"{len(self.digests)} digests)"
            )

    def __len__(self) -> int:
        return len(self.steps)

    @property
    def final_digest(self) -> int:
        """Digest of the mesh after the last step (the input digest for an empty trace)."""
        return self.digests[-1] if self.digests else self.input_digest

    def parameter(self, name: str, default: Any = None) -> Any:
        """The value of one run parameter."""
        return dict(self.parameters).get(name, default)


def trace_of(
    start: Mesh2, transient: Transient2, parameters: Mapping[str, Any] | None = None
) -> Trace:
    """The trace recorded by ``transient`` since it was opened on ``start``."""
    from geomexact import __version__

    return Trace(
        start.digest, transient.steps, transient.step_digests, parameters, __version__
    )


# -- replay -------------------------------------------------------------------------------
def replay_iter(start: Mesh2, trace: Trace, until: int | None = None) -> Iterator[Mesh2]:
    """Yield the mesh after each of the first ``until`` steps (all when None), checking
    every digest.  Raises :class:`TraceError` when ``start`` is not the trace's input or a
    step's result differs from the recorded digest."""
    check_start(start, trace)
    count = _count(trace, until)
    mesh = start
    for index in range(count):
        transient = Transient2(mesh)
        apply_checked(transient, trace, index)
        mesh = transient.seal()
        yield mesh


def replay(start: Mesh2, trace: Trace, until: int | None = None) -> Mesh2:
    """The mesh after the first ``until`` steps of ``trace`` (all when None), replayed on
    ``start`` in one batch and checked step by step against the recorded digests."""
    check_start(start, trace)
    count = _count(trace, until)
    transient = Transient2(start)
    for index in range(count):
        apply_checked(transient, trace, index)
    return transient.seal()


def check_start(start: Mesh2, trace: Trace) -> None:
    """Raise :class:`TraceError` unless ``start`` is the mesh ``trace`` was recorded on."""
    if start.digest != trace.input_digest:
        raise TraceError(
            f"this trace was recorded on a mesh with digest {trace.input_digest:032x}, "
            f"but the given mesh has digest {start.digest:032x}: it is not the trace's input"
        )


def _count(trace: Trace, until: int | None) -> int:
    if until is None:
        return len(trace.steps)
    if not 0 <= until <= len(trace.steps):
        raise TraceError(f"--until {until} is outside 0..{len(trace.steps)}")
    return until


def apply_checked(transient: Transient2, trace: Trace, index: int) -> None:
    """Apply step ``index`` (0-based) of ``trace`` to ``transient`` and check the digest
    after it; :class:`TraceError` names the step when it cannot be applied or diverges."""
    step = trace.steps[index]
    try:
        apply_in(transient, step)
    except ValueError as error:
        raise TraceError(
            f"step {index + 1} ({step}) cannot be applied: {error}", index + 1
        ) from error
    if transient.digest != trace.digests[index]:
        raise TraceError(
            f"step {index + 1} ({step}) gave digest {transient.digest:032x}, "
            f"the trace recorded {trace.digests[index]:032x}",
            index + 1,
        )


def first_divergence(a: Trace, b: Trace) -> int | None:
    """Index (0-based) of the first step at which the two traces differ in step or digest;
    0 when their inputs differ; the shorter length when one is a prefix of the other; None
    when they are identical."""
    if a.input_digest != b.input_digest:
        return 0
    for index, (step_a, step_b, digest_a, digest_b) in enumerate(
        zip(a.steps, b.steps, a.digests, b.digests, strict=False)
    ):
        if step_a != step_b or digest_a != digest_b:
            return index
    if len(a) != len(b):
        return min(len(a), len(b))
    return None


# -- files --------------------------------------------------------------------------------
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
    from geomexact.io.files import write_lines_atomic

    write_lines_atomic(path, trace_lines(trace), overwrite=overwrite)


def read_trace(path: str | Path) -> Trace:
    """Read a trace file (see :func:`parse_trace`)."""
    from geomexact.io.files import read_text

    return parse_trace(read_text(path), str(path))

