"""The format registry's record type and the machinery every format module shares.

A :class:`Format` names a file format, the extensions that select it, the kinds of value
it reads and writes, and its ``read`` / ``write`` functions.  The registry itself
(``geomexact.io.FORMATS``) is assembled in :mod:`geomexact.io` from the format modules.

The rest of this module is what the readers and writers have in common, so each rule is
written once (``specs/formats/registry.md``):

- :func:`data_lines` / :class:`Lines`: text split into numbered lines of tokens, ``#``
  comments and blank lines dropped, with a cursor that reports a truncated file;
- :func:`parse_int` / :func:`parse_number`: tokens to integers and exact rationals, every
  failure a :class:`FormatError` naming the file and the line;
- :func:`build_mesh`: vertex and triangle tables to a :class:`Mesh2`, checking indices,
  duplicate vertices, degenerate triangles, orientation (all clockwise is reversed and
  noted; mixed is an error naming one triangle of each) and overlaps;
- :class:`NumberText`, :func:`dropped_parts` and :func:`write_files`: number text
  (exact decimal, ``p/q`` or nearest double, counting what is rounded), what a format
  cannot hold, and the all-or-nothing, never-overwrite-by-default atomic writing of one
  or more files, reported as a :class:`WriteReport`.
"""

from __future__ import annotations

import hashlib
import math
import os
from collections.abc import Callable, Collection, Iterable, Iterator, Sequence
from pathlib import Path
from typing import Any, Literal, Protocol, TypeAlias, TypeVar

import attrs
import gmpy2

from geomexact.errors import (
    FormatError,
    OverwriteError,
    PreconditionError,
    RationalParseError,
    UnsupportedValueError,
)
from geomexact.io.files import open_regular, output_set, read_lines
from geomexact.kernel.numbers import (
    ZERO,
    Rational,
    dyadic_decimal,
    exact_decimal,
    floor_log2,
    parse_rational,
    to_float,
)
from geomexact.kernel.points import Point2
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates2d import orient2d
from geomexact.kernel.vectorising import worth_vectorising
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Attributes, Mesh2, empty_mesh
from geomexact.mesh2d.transient import Transient2
from geomexact.mesh3d.mixed.cell_data import MixedMeshData
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.snapshot import Mesh3

Value: TypeAlias = Mesh2 | PSLG | PolygonMesh | Mesh3 | MixedMesh3 | MixedMeshData
"""What a reader returns (never a :class:`MixedMeshData`: a reader returns the mesh) and
a writer accepts."""

Tokens: TypeAlias = list[str]
_Written = TypeVar("_Written", bound=Value)
NumberedLine: TypeAlias = tuple[int, Tokens]


class Reader(Protocol):
    """``read(path)`` -> (value, notes)."""

    def __call__(self, path: Path, /) -> tuple[Value, list[str]]: ...


class Writer(Protocol):
    """``write(path, value, overwrite=..., numbers=...)`` -> what was written
    (:class:`WriteReport`)."""

    def __call__(
        self, path: Path, value: Value, /, *, overwrite: bool, numbers: NumberStyle
    ) -> WriteReport: ...


def single_output(path: Path) -> tuple[Path, ...]:
    """The files a one-file format writes for ``path``: ``path`` itself."""
    return (path,)


MESHIO_EXTENSIONS = (".vtk", ".vtu", ".xdmf", ".xmf", ".msh", ".mesh", ".obj", ".ply")
"""The extensions read and written through meshio
(:mod:`geomexact.io.meshio_bridge`)."""


@attrs.frozen(slots=True)
class Format:
    """A registered file format.

    ``extensions`` are lower-case with the dot (``".ele"``); ``kinds`` are the value types
    ``write`` accepts (and ``read`` may return); ``outputs(path)`` are the files a write
    to ``path`` may create.
    """

    name: str
    extensions: tuple[str, ...]
    description: str
    read: Reader
    write: Writer
    kinds: tuple[type, ...]
    outputs: Callable[[Path], tuple[Path, ...]] = attrs.field(default=single_output)


# -----------------------------------------------------------------------------------------
# reading text
# -----------------------------------------------------------------------------------------
QUOTE_LIMIT = 200
"""The most characters of a line or token that a message quotes."""


def quoted(text: str, limit: int = QUOTE_LIMIT) -> str:
    """``repr(text)``, or for a text longer than ``limit`` characters the repr of its
    start, ``…`` and its length: a message never copies a huge line."""
    if len(text) <= limit:
        return repr(text)
    return f"{text[:limit]!r}… ({len(text):,} characters)"


def clipped(text: str, limit: int = QUOTE_LIMIT) -> str:
    """``text`` itself, or for a text longer than ``limit`` characters its start, ``…``
    and its length (for numbers shown as they are written, without quotes)."""
    if len(text) <= limit:
        return text
    return f"{text[:limit]}… ({len(text):,} characters)"


def quoted_tokens(tokens: Sequence[str], limit: int = QUOTE_LIMIT) -> str:
    """:func:`quoted` of the tokens joined by spaces, joining only as many as it shows."""
    shown: list[str] = []
    size = 0
    for token in tokens:
        shown.append(token)
        size += len(token) + 1
        if size > limit:
            break
    text = " ".join(shown)
    if len(shown) == len(tokens):
        return quoted(text, limit)
    total = sum(len(token) for token in tokens) + len(tokens) - 1
    return f"{text[:limit]!r}… ({total:,} characters)"


def token_lines(rows: Iterable[tuple[int, str]]) -> Iterator[NumberedLine]:
    """The non-blank rows as (line number, tokens), everything from a ``#`` to the end of
    its row removed; tokens split on any whitespace.  Lazy: a file is read as far as its
    reader asks."""
    for number, line in rows:
        if "#" in line:
            line = line[: line.index("#")]
        tokens = line.split()
        if tokens:
            yield number, tokens


def data_lines(text: str) -> list[NumberedLine]:
    """The non-blank lines of ``text`` as (1-based line number, tokens), with everything
    from a ``#`` to the end of its line removed.  Lines are split on ``\\n`` only (so line
    numbers agree with ``read_text``'s and with editors'); tokens on any whitespace."""
    text = text.removeprefix("\ufeff")  # a byte-order mark is not data
    return list(token_lines(enumerate(text.split("\n"), start=1)))


def file_lines(path: Path) -> Lines:
    """The data lines of the file ``path`` (:func:`token_lines` of
    :func:`geomexact.io.files.read_lines`), streamed."""
    return Lines(str(path), token_lines(read_lines(path)))


class Lines:
    """A cursor over the numbered lines of one file, pulled one at a time (a reader never
    holds the file's text); running out is a :class:`FormatError` saying what was
    expected (a truncated file)."""

    __slots__ = ("_lines", "_pending", "last_line", "path")

    def __init__(self, path: str, lines: Iterable[NumberedLine]) -> None:
        self.path = path
        self._lines = iter(lines)
        self._pending: NumberedLine | None = None
        self.last_line: int | None = None  # the last line handed out

    def _peek(self) -> NumberedLine | None:
        if self._pending is None:
            self._pending = next(self._lines, None)
        return self._pending

    def next(self, what: str) -> NumberedLine:
        """The next line, or a FormatError "file ends before <what>"."""
        line = self._peek()
        if line is None:
            raise FormatError(self.path, self.last_line, f"the file ends before {what}")
        self._pending = None
        self.last_line = line[0]
        return line

    def next_item(self, index: int, count: int, item: str, plural: str) -> NumberedLine:
        """The line of item ``index`` (0-based) of a section announcing ``count`` items
        (``item``: how a message names it, e.g. ``"vertex 3"``); at the end of the file a
        FormatError "expected <count> <plural>, found <index>"."""
        line = self._peek()
        if line is None:
            raise FormatError(
                self.path,
                self.last_line,
                f"expected {clipped(str(count), 40)} {plural}, found {index}: the file ends "
                f"before {clipped(item, 80)}",
            )
        return self.next(item)

    def at_end(self) -> bool:
        """True when every line was consumed."""
        return self._peek() is None

    def rest(self) -> list[NumberedLine]:
        """The lines not consumed yet (and consume them)."""
        remaining = [] if self._peek() is None else [self.next("the rest")]
        remaining.extend(self._lines)
        return remaining

    def expect_end(self, what: str) -> None:
        """FormatError when lines remain after the last section ``what``."""
        line = self._peek()
        if line is not None:
            number, tokens = line
            raise FormatError(
                self.path, number, f"unexpected data after {what}: {quoted_tokens(tokens)}"
            )


def is_count_line(tokens: Sequence[str], most: int) -> bool:
    """True when ``tokens`` are 1 to ``most`` integers: the shape of a section header
    (``count [markers]``), which a line of a section's items never has."""
    return 0 < len(tokens) <= most and all(token.lstrip("+-").isdigit() for token in tokens)


def section_too_short(
    path: str, line: int, count: int, found: int, plural: str, header: int | None,
    problem: str,
) -> FormatError:
    """The error of a section whose header (on line ``header``) announces ``count`` items
    when the file has ``found``: line ``line`` already has the shape of what follows
    (``problem`` says why it is not an item)."""
    where = f" on line {header}" if header is not None else ""
    return FormatError(
        path,
        line,
        f"expected {clipped(str(count), 40)} {plural}, found {found}: this line is not one "
        f"of them ({problem}); is the count{where} right?",
    )


PROBLEM_LIMIT = 1000
"""The longest problem text of a reader's FormatError (:func:`bounded`)."""


def bounded(error: FormatError) -> FormatError:
    """``error``, or when its problem is longer than :data:`PROBLEM_LIMIT` characters (an
    absurd number quoted whole, e.g. a 4000-digit vertex label) the same error with the
    middle of the problem cut: the safety net behind every reader's quoting."""
    problem = error.problem
    if len(problem) <= PROBLEM_LIMIT:
        return error
    head, tail = problem[: PROBLEM_LIMIT * 2 // 3], problem[-PROBLEM_LIMIT // 4 :]
    return FormatError(
        error.path, error.line, f"{head}… ({len(problem):,} characters) …{tail}"
    )


def counted(count: int, singular: str, plural: str | None = None) -> str:
    """``"1 vertex"``, ``"2 vertices"``: a count with its noun, for notes and messages."""
    return f"{count} {singular if count == 1 else plural or singular + 's'}"


def all_clockwise_note(count: int, noun: str) -> str:
    """The note of a reader that reversed every one of ``count`` clockwise elements."""
    if count == 1:
        return f"the only {noun} was clockwise; reversed it"
    return f"all {count} {noun}s were clockwise; reversed them"


def parse_int(path: str, line: int, token: str, what: str) -> int:
    """``token`` as an integer, or a FormatError naming ``what`` it should be."""
    try:
        if token.isascii():
            return int(token)
    except ValueError:
        if token.lstrip("+-").isdigit():  # more digits than int() converts
            raise FormatError(
                path, line, f"{what}: {quoted(token)} is too large ({len(token):,} digits)"
            ) from None
    raise FormatError(path, line, f"{what}: {quoted(token)} is not an integer")


def parse_number(path: str, line: int, token: str, what: str) -> Rational:
    """``token`` parsed exactly (:func:`geomexact.kernel.numbers.parse_rational`), or a
    FormatError embedding the parser's reason."""
    try:
        return parse_rational(token)
    except RationalParseError as error:
        raise FormatError(
            path, line, f"{what}: cannot read {quoted(token)} as a number: {error.problem}"
        ) from error


def parse_count(path: str, line: int, token: str, what: str) -> int:
    """A non-negative integer count."""
    value = parse_int(path, line, token, what)
    if value < 0:
        raise FormatError(path, line, f"{what} is negative ({value})")
    return value


def expect_fields(path: str, line: int, tokens: Tokens, least: int, what: str) -> None:
    """FormatError when ``tokens`` has fewer than ``least`` fields."""
    if len(tokens) < least:
        raise FormatError(
            path,
            line,
            f"{what} needs {least} fields, found {len(tokens)}: {quoted_tokens(tokens)}",
        )


def expect_exact_fields(path: str, line: int, tokens: Tokens, count: int, what: str) -> None:
    """FormatError when ``tokens`` does not have exactly ``count`` fields."""
    if len(tokens) != count:
        raise FormatError(
            path,
            line,
            f"{what} needs {count} fields, found {len(tokens)}: {quoted_tokens(tokens)}",
        )


def expect_field_range(
    path: str, line: int, tokens: Tokens, low: int, high: int, what: str
) -> None:
    """FormatError naming ``what`` (the record's expected form) when ``tokens`` has fewer
    than ``low`` or more than ``high`` fields."""
    if not low <= len(tokens) <= high:
        raise FormatError(path, line, f"expected {what}, found {quoted_tokens(tokens)}")


def expect_header_fields(path: str, line: int, tokens: Tokens, header: str, shape: str) -> None:
    """FormatError when the header line ``tokens`` has more fields than its form
    ``shape`` (``"count 4 attributes"``) names; ``header`` says which header it is
    (``"the .ele header"``)."""
    if len(tokens) > len(shape.split()):
        raise FormatError(path, line, f"{header} is '{shape}', found {len(tokens)} fields")


def read_header(path: Path, header: str, shape: str) -> tuple[Lines, int, Tokens]:
    """The lines of the file ``path``, after its header line of form ``shape``, and that
    line's number and tokens (FormatErrors of :func:`expect_header_fields`)."""
    lines = file_lines(path)
    number, tokens = lines.next(f"the header '{shape}'")
    expect_header_fields(str(path), number, tokens, header, shape)
    return lines, number, tokens


def parse_marker_flag(path: str, line: int, tokens: Tokens, index: int, what: str) -> int:
    """The marker count ``what`` (``"face marker count"``) at ``tokens[index]`` of a
    header, 0 when the header ends before it; a FormatError unless it is 0 or 1."""
    markers = parse_int(path, line, tokens[index], what) if len(tokens) > index else 0
    if markers not in (0, 1):
        raise FormatError(path, line, f"{what} must be 0 or 1, not {markers}")
    return markers


@attrs.frozen(slots=True)
class FixedField:
    """A header field that must hold ``value`` (the corners of a ``.ele`` triangle, the
    dimension of a ``.node``): ``what`` names it in :func:`parse_int`'s messages,
    ``default`` is its value when the header ends before it, and ``problem(found)`` is the
    message of any other value ``found``."""

    what: str
    value: int
    default: int
    problem: Callable[[int], str]

    def check(self, path: str, line: int, tokens: Tokens, index: int) -> None:
        """FormatError ``problem(found)`` unless the field ``tokens[index]`` of the header
        (``default`` when the header ends before it) is ``value``."""
        found = (parse_int(path, line, tokens[index], self.what) if len(tokens) > index
                 else self.default)
        if found != self.value:
            raise FormatError(path, line, self.problem(found))


@attrs.frozen(slots=True)
class HeaderCounts:
    """What the header line ``count field attributes markers`` of a Triangle or TetGen file
    (on line ``line``) says; a field it leaves out is 0."""

    line: int
    count: int
    attributes: int
    markers: int


@attrs.frozen(slots=True)
class CountHeader:
    """The header line ``count field [attributes [markers]]`` of a Triangle or TetGen file:
    ``header`` names it in messages (``"the .ele header"``), ``shape`` is its form
    (``"count corners attributes"``, which has no markers field), ``count`` names its
    first field and ``field`` its second."""

    header: str
    shape: str
    count: str
    field: FixedField

    def parse(self, path: str, line: int, tokens: Tokens) -> HeaderCounts:
        """The counts of the header ``tokens`` on line ``line`` of ``path``: FormatErrors
        of :func:`expect_header_fields`, :func:`parse_count`, :meth:`FixedField.check` and
        :func:`parse_marker_flag`."""
        expect_header_fields(path, line, tokens, self.header, self.shape)
        count = parse_count(path, line, tokens[0], self.count)
        self.field.check(path, line, tokens, 1)
        attributes = parse_count(path, line, tokens[2], "attribute count") if len(tokens) > 2 else 0
        markers = parse_marker_flag(path, line, tokens, 3, "boundary marker count")
        return HeaderCounts(line, count, attributes, markers)

    def read(self, path: Path) -> tuple[Lines, HeaderCounts]:
        """The lines of the file ``path`` after its header line, and the counts of that
        line (:meth:`parse`)."""
        lines = file_lines(path)
        line, tokens = lines.next(f"the header '{self.shape}'")
        return lines, self.parse(str(path), line, tokens)


def check_numbering(path: str, line: int, label: int, index: int, base: int, noun: str) -> int:
    """The numbering base of a file whose ``noun``s are numbered consecutively from 0 or
    1: the first label sets it (``index == 0``), each later one must follow; returns the
    base, or raises a FormatError naming the line."""
    if index == 0:
        if label not in (0, 1):
            raise FormatError(
                path, line, f"the first {noun} is numbered {label}; it must be 0 or 1"
            )
        return label
    if label != index + base:
        raise FormatError(
            path, line, f"{noun} numbered {label}, expected {index + base} (consecutive)"
        )
    return base


def check_index(path: str, line: int, index: int, count: int, base: int, what: str) -> int:
    """The 0-based id of a 0- or 1-based file index, or a FormatError when out of range."""
    value = index - base
    if not 0 <= value < count:
        allowed = "there are none" if count == 0 else f"expected {base}..{count - 1 + base}"
        raise FormatError(path, line, f"{what} {index} is out of range ({allowed})")
    return value


@attrs.frozen(slots=True)
class SourceLines:
    """Where the items of a value came from: the file and line of each vertex, segment,
    hole and region seed (None: no line, e.g. a binary file), and the file's numbering
    base of vertices — for messages in the words of the input, such as
    ``"x.poly:12 and x.poly:16: segments (3, 4) and (7, 8) cross"``."""

    vertex_file: str
    vertex_lines: tuple[int | None, ...]
    segment_file: str = ""
    segment_lines: tuple[int | None, ...] = ()
    hole_lines: tuple[int | None, ...] = ()
    region_lines: tuple[int | None, ...] = ()
    base: int = 0

    @staticmethod
    def _where(path: str, lines: Sequence[int | None], index: int) -> str:
        line = lines[index] if 0 <= index < len(lines) else None
        return f"{path}:{line}" if line is not None else path

    def vertex(self, index: int) -> str:
        """``file:line`` of vertex ``index`` (0-based)."""
        return self._where(self.vertex_file, self.vertex_lines, index)

    def segment(self, index: int) -> str:
        """``file:line`` of segment ``index`` (0-based, in file order)."""
        return self._where(self.segment_file or self.vertex_file, self.segment_lines, index)

    def hole(self, index: int) -> str:
        """``file:line`` of hole seed ``index``."""
        return self._where(self.segment_file or self.vertex_file, self.hole_lines, index)

    def region(self, index: int) -> str:
        """``file:line`` of region seed ``index``."""
        return self._where(self.segment_file or self.vertex_file, self.region_lines, index)


@attrs.frozen(slots=True)
class Reading:
    """What a reader read: the value, its notes and, for the readers that keep them, the
    :class:`SourceLines` of its items."""

    value: Value
    notes: list[str]
    sources: SourceLines | None = None


# -----------------------------------------------------------------------------------------
# building a mesh
# -----------------------------------------------------------------------------------------
@attrs.frozen(slots=True)
class TriangleTable:
    """Triangles as read from a file: 0-based vertex triples in file order, with where
    each came from (its line, or None when the source has no lines) and, optionally, the
    file's own numbering of triangles and vertices for messages."""

    path: str
    triangles: Sequence[tuple[int, int, int]]
    lines: Sequence[int | None]
    attributes: Sequence[Attributes] | None = None
    noun: str = "triangle"
    first_number: int = 0
    vertex_base: int = 0

    def describe(self, index: int) -> str:
        a, b, c = (v + self.vertex_base for v in self.triangles[index])
        line = self.lines[index]
        where = f" on line {line}" if line is not None else ""
        return f"{self.noun} {index + self.first_number} ({a}, {b}, {c}){where}"


def check_distinct_points(
    path: str,
    points: Sequence[Point2],
    lines: Sequence[int | None],
    used: set[int],
    notes: list[str],
    vertex_base: int = 0,
) -> None:
    """FormatError when two vertices used by triangles have identical exact coordinates
    (a mesh needs distinct corners), naming both and the line of the second.  A copy in
    no triangle is harmless (such files exist: meshio output with stray corner points) and
    is only noted."""
    seen: dict[tuple[Rational, Rational], int] = {}
    unused_copies: list[tuple[int, int]] = []
    for index, point in enumerate(points):
        key = (point.x, point.y)
        first = seen.get(key)
        if first is None:
            seen[key] = index
            continue
        if first in used and index in used:
            first_line = lines[first]
            where = f" (line {first_line})" if first_line is not None else ""
            raise FormatError(
                path,
                lines[index],
                f"vertex {index + vertex_base} ({point.x}, {point.y}) has the same "
                f"coordinates as vertex {first + vertex_base}{where}; a mesh needs "
                "distinct vertices",
            )
        if index in used:  # the triangles use the later copy: remember it instead
            seen[key] = index
        unused_copies.append((index if index not in used else first, seen[key]))
    if unused_copies:
        copy, original = unused_copies[0]
        notes.append(
            f"{counted(len(unused_copies), 'vertex', 'vertices')} in no triangle "
            f"{'repeats' if len(unused_copies) == 1 else 'repeat'} another vertex's "
            f"coordinates (vertex {copy + vertex_base} repeats vertex "
            f"{original + vertex_base}); kept them"
        )


def note_duplicate_points(
    points: Sequence[Point2], lines: Sequence[int | None], notes: list[str], base: int = 0
) -> None:
    """Note (not an error) vertices that repeat an earlier vertex's exact coordinates:
    allowed in a PSLG or a polygon mesh."""
    seen: dict[tuple[Rational, Rational], int] = {}
    duplicates = 0
    example = ""
    for index, point in enumerate(points):
        first = seen.setdefault((point.x, point.y), index)
        if first != index:
            duplicates += 1
            if not example:
                line = lines[index]
                where = f" on line {line}" if line is not None else ""
                example = f" (vertex {index + base}{where} repeats vertex {first + base})"
    if duplicates:
        notes.append(
            f"{counted(duplicates, 'vertex', 'vertices')} "
            f"{'repeats' if duplicates == 1 else 'repeat'} an earlier vertex's "
            f"coordinates{example}"
        )


class Orienter:
    """Orients the triangles of a table one at a time (exact ``orient2d``), by the rules
    of :func:`orient_triangles`, so that a reader can stop at the line of the first
    degenerate or mixed triangle instead of after reading the whole file.

    ``vertices``: the vertex file and the line of each vertex.  With it, before reporting
    an orientation problem, the vertices used so far are checked for duplicates (as
    :func:`build_mesh` does first): two corners at one point make a triangle degenerate
    or turn it, and the duplicate is the problem to name."""

    __slots__ = (
        "first_ccw", "first_cw", "individually", "oriented", "points", "reversed_count",
        "table", "vertices",
    )

    def __init__(
        self,
        table: TriangleTable,
        points: Sequence[Point2],
        *,
        individually: bool,
        vertices: tuple[str, Sequence[int | None]] | None = None,
    ) -> None:
        self.table = table
        self.points = points
        self.individually = individually
        self.vertices = vertices
        self.oriented: list[tuple[int, int, int]] = []
        self.first_cw: int | None = None
        self.first_ccw: int | None = None
        self.reversed_count = 0

    def _problem(self, index: int, problem: str) -> FormatError:
        """The error of triangle ``index`` (or of a duplicate vertex behind it)."""
        table = self.table
        if self.vertices is not None:
            path, lines = self.vertices
            used = {v for triangle in table.triangles[: index + 1] for v in triangle}
            check_distinct_points(path, self.points, lines, used, [], table.vertex_base)
        return FormatError(table.path, table.lines[index], problem)

    def add(self, index: int) -> None:
        """Orient triangle ``index`` of the table (the next one); FormatError for a
        repeated or collinear corner and for the first triangle that mixes orientations."""
        table, points = self.table, self.points
        a, b, c = table.triangles[index]
        if a in (b, c) or b == c:
            raise FormatError(
                table.path, table.lines[index], f"{table.describe(index)} repeats a vertex"
            )
        orientation = orient2d(points[a], points[b], points[c])
        if orientation == Orientation.COLLINEAR:
            raise self._problem(
                index, f"{table.describe(index)} is degenerate: its corners are collinear"
            )
        if orientation == Orientation.CLOCKWISE:
            if self.first_cw is None:
                self.first_cw = index
            self.oriented.append((a, c, b))
            self.reversed_count += 1
        else:
            if self.first_ccw is None:
                self.first_ccw = index
            self.oriented.append((a, b, c))
        first_cw, first_ccw = self.first_cw, self.first_ccw
        if not self.individually and first_cw is not None and first_ccw is not None:
            raise self._problem(
                max(first_cw, first_ccw),
                f"{table.noun}s have mixed orientations: {table.describe(first_cw)} is "
                f"clockwise but {table.describe(first_ccw)} is counter-clockwise",
            )

    def finish(self, notes: list[str]) -> list[tuple[int, int, int]]:
        """The oriented triangles (all added), noting how many were reversed."""
        total, reversed_count, noun = len(self.oriented), self.reversed_count, self.table.noun
        if reversed_count:
            if reversed_count == total:
                notes.append(all_clockwise_note(total, noun))
            else:
                notes.append(
                    f"{reversed_count} of {counted(total, noun)} were clockwise; reversed "
                    f"{'it' if reversed_count == 1 else 'them'}"
                )
        return self.oriented


@attrs.frozen(slots=True)
class BulkOrientation:
    """Triangles oriented in bulk by a reader's fast path (:mod:`geomexact.io.bulk`):
    ``rows`` (T x 3 int64), all counter-clockwise; ``reversed_count`` of them were
    clockwise in the file (0 or all: a fast path leaves mixed files to the
    :class:`Orienter`)."""

    rows: Any
    reversed_count: int
    noun: str = "triangle"

    def finish(self, notes: list[str]) -> None:
        """Note the reversal, as :meth:`Orienter.finish` does."""
        if self.reversed_count:
            notes.append(all_clockwise_note(self.reversed_count, self.noun))


def orient_triangles(
    table: TriangleTable, points: Sequence[Point2], *, individually: bool, notes: list[str]
) -> list[tuple[int, int, int]]:
    """The triangles of ``table`` made counter-clockwise (exact ``orient2d``).

    A degenerate triangle (a repeated or collinear corner) is a FormatError naming it.
    With ``individually`` each clockwise triangle is reversed.  Otherwise the file must be
    consistent: all clockwise is reversed (and noted), a mix is a FormatError naming the
    first clockwise and the first counter-clockwise triangle.
    """
    orienter = Orienter(table, points, individually=individually)
    for index in range(len(table.triangles)):
        orienter.add(index)
    return orienter.finish(notes)


def build_mesh(
    points: Sequence[Point2],
    point_lines: Sequence[int | None],
    table: TriangleTable,
    *,
    point_path: str,
    notes: list[str],
    vertex_markers: Sequence[int] | None = None,
    vertex_attributes: Sequence[Attributes] | None = None,
    segments: Sequence[tuple[int, int, int]] = (),
    segment_lines: Sequence[int | None] = (),
    segment_path: str | None = None,
    orient_individually: bool = False,
    orienter: Orienter | BulkOrientation | None = None,
) -> Mesh2:
    """A :class:`Mesh2` from checked tables (indices already 0-based and in range).

    Checks, each a FormatError naming the file and line: duplicate vertices, degenerate
    triangles, orientation (see :func:`orient_triangles`), two triangles on the same side
    of an edge (overlap), segments with equal ends.  Notes vertices in no triangle.
    ``orienter``: the reader's, which oriented every triangle as it was read.
    """
    used = {vertex for triangle in table.triangles for vertex in triangle}
    check_distinct_points(point_path, points, point_lines, used, notes, table.vertex_base)
    rows: Any = None
    oriented: list[tuple[int, int, int]]
    if isinstance(orienter, BulkOrientation):
        rows = orienter.rows
        orienter.finish(notes)
        oriented = []
    elif orienter is not None and len(orienter.oriented) == len(table.triangles):
        oriented = orienter.finish(notes)
    else:
        oriented = orient_triangles(
            table, points, individually=orient_individually, notes=notes
        )
    triangle_attributes = table.attributes
    built = None
    if triangle_attributes is None and (
            rows is not None or worth_vectorising(len(oriented), 0)):
        # imported here: the bulk module builds on the tables of this one (and NumPy's
        # import is paid only for a mesh big enough to gain from it)
        import numpy as np

        from geomexact.io.bulk import bulk_mesh2

        if rows is None:
            rows = np.array(oriented, dtype=np.int64).reshape(-1, 3)
        built = bulk_mesh2(points, rows, vertex_markers, vertex_attributes)
    if built is not None and not segments:
        # nothing to add: the bulk mesh, its tables still arrays until something needs them
        return _noted_unused(built, points, used, table, notes)
    if built is not None:
        transient = built.transient()
    else:  # triangle attributes, or an overlap to report: one triangle at a time
        if rows is not None and not oriented:
            oriented = [(a, b, c) for a, b, c in rows.tolist()]
        transient = _transient_mesh(points, vertex_markers, vertex_attributes)
        for index, (a, b, c) in enumerate(oriented):
            values = triangle_attributes[index] if triangle_attributes is not None else None
            try:
                transient.add_triangle(a, b, c, values or None)
            except PreconditionError as error:
                raise FormatError(
                    table.path, table.lines[index], _overlap_problem(table, oriented, index)
                ) from error
    segment_file = segment_path or table.path
    not_edges = 0
    for index, (u, v, marker) in enumerate(segments):
        line = segment_lines[index] if index < len(segment_lines) else None
        if u == v:
            raise FormatError(
                segment_file,
                line,
                f"segment ({u + table.vertex_base}, {v + table.vertex_base}) has equal ends",
            )
        if transient.segment_marker(u, v) is not None:
            notes.append(
                f"segment ({u + table.vertex_base}, {v + table.vertex_base}) is listed twice"
                + (f" (line {line})" if line is not None else "")
                + "; kept the last marker"
            )
        transient.set_segment(u, v, marker)
        if transient.apex(u, v) is None and transient.apex(v, u) is None:
            not_edges += 1
    mesh = transient.seal()
    if not_edges:
        notes.append(
            f"{counted(not_edges, 'segment')} {'is' if not_edges == 1 else 'are'} not an "
            "edge of the mesh (validate reports them)"
        )
    return _noted_unused(mesh, points, used, table, notes)


def _noted_unused(mesh: Mesh2, points: Sequence[Point2], used: set[int], table: TriangleTable,
                  notes: list[str]) -> Mesh2:
    """``mesh``, with a note when some of the ``points`` are in no triangle."""
    unused = len(points) - len(used)
    if unused and table.triangles:
        notes.append(
            f"{unused} of {counted(len(points), 'vertex', 'vertices')} "
            f"{'is' if unused == 1 else 'are'} in no triangle"
        )
    return mesh


def _transient_mesh(
    points: Sequence[Point2],
    vertex_markers: Sequence[int] | None,
    vertex_attributes: Sequence[Attributes] | None,
) -> Transient2:
    """A transient holding ``points`` with their markers and attributes, no triangle."""
    transient = Transient2(empty_mesh())
    for index, point in enumerate(points):
        marker = vertex_markers[index] if vertex_markers is not None else 0
        attributes = vertex_attributes[index] if vertex_attributes is not None else ()
        transient.add_vertex(point, marker, attributes)
    return transient


def _overlap_problem(
    table: TriangleTable, oriented: Sequence[tuple[int, int, int]], index: int
) -> str:
    a, b, c = oriented[index]
    edges = {(a, b), (b, c), (c, a)}
    for earlier in range(index):
        p, q, r = oriented[earlier]
        shared = edges & {(p, q), (q, r), (r, p)}
        if shared:
            u, v = min(shared)
            base = table.vertex_base
            return (
                f"{table.describe(index)} and {table.describe(earlier)} lie on the same "
                f"side of edge ({u + base}, {v + base}): the triangles overlap"
            )
    return f"{table.describe(index)} overlaps an earlier {table.noun}"  # pragma: no cover


def expected_neighbours(
    triangles: Sequence[tuple[int, int, int]],
) -> list[tuple[int, int, int]]:
    """For each triangle (a, b, c), the indices of the triangles across the edges opposite
    a, b and c (-1 for none), as Triangle's ``.neigh`` lists them.  The triangles must be
    consistently oriented (all clockwise or all counter-clockwise, no overlap), as
    :func:`build_mesh` checks: the neighbour across (b, c) is the owner of (c, b)."""
    owner: dict[int, int] = {}
    for index, (a, b, c) in enumerate(triangles):
        owner[(a << 32) | b] = index
        owner[(b << 32) | c] = index
        owner[(c << 32) | a] = index
    get = owner.get
    return [
        (get((c << 32) | b, -1), get((a << 32) | c, -1), get((b << 32) | a, -1))
        for a, b, c in triangles
    ]


# -----------------------------------------------------------------------------------------
# writing
# -----------------------------------------------------------------------------------------
NumberStyle: TypeAlias = Literal["decimal", "exact", "float"]
"""How a writer writes numbers: ``"decimal"`` (the default) writes every number with a
finite decimal expansion as that exact decimal and rounds only the others to the nearest
double; ``"exact"`` writes those others as ``p/q``; ``"float"`` writes the nearest double
of every number.  Every rounded number is counted (:class:`WriteReport`)."""

NUMBER_STYLES: tuple[NumberStyle, ...] = ("decimal", "exact", "float")

_EXACT_INTEGER_LIMIT = 1 << 53
_SMALLEST_NORMAL = 2.0**-1022
_ZEROS_WORTH_AN_EXPONENT = 8
_ROUNDED_DIGITS = 17  # significant digits of a rounded number outside the normal doubles


@attrs.frozen(slots=True)
class WriteReport:
    """What a writer wrote: the ``paths``, how many numbers it ``rounded`` (written as a
    nearby value, not exactly), and what the format could not hold (``dropped``: one
    phrase per part, such as ``"12 segments"``)."""

    paths: tuple[Path, ...]
    rounded: int = 0
    dropped: tuple[str, ...] = ()


class NumberText:
    """The text of each number of one write, in one :data:`NumberStyle`, counting the
    numbers it rounds.  A transient: one per write call.

    Each distinct value is formatted once (a mesh repeats its coordinates: a refined grid
    has a few hundred distinct ones among 10^5 vertices), through :func:`~geomexact.
    kernel.numbers.dyadic_decimal` when its denominator is a power of two; a rounded value
    is counted at every occurrence, as when it was formatted each time."""

    __slots__ = ("_cache", "rounded", "style")

    def __init__(self, style: NumberStyle) -> None:
        if style not in NUMBER_STYLES:
            raise ValueError(f"unknown number style {style!r} (known: {NUMBER_STYLES})")
        self.style = style
        self.rounded = 0
        self._cache: dict[Rational, tuple[str, bool]] = {}

    def __call__(self, value: Rational) -> str:
        known = self._cache.get(value)
        if known is None:
            known = self._cache[value] = self._text(value)
        if known[1]:
            self.rounded += 1
        return known[0]

    def texts(self, values: Iterable[Rational]) -> list[str]:
        """The text of each of ``values`` (:meth:`__call__` of each, in bulk)."""
        cache = self._cache
        get = cache.get
        out: list[str] = []
        append = out.append
        rounded = 0
        for value in values:
            known = get(value)
            if known is None:
                known = cache[value] = self._text(value)
            if known[1]:
                rounded += 1
            append(known[0])
        self.rounded += rounded
        return out

    def _text(self, value: Rational) -> tuple[str, bool]:
        """(text, rounded) of one value."""
        if self.style == "float":
            if value.denominator == 1 and abs(value.numerator) <= _EXACT_INTEGER_LIMIT:
                return mpz_text(value.numerator), False
        else:
            text = dyadic_decimal(value, plain_within=_ZEROS_WORTH_AN_EXPONENT)
            if text is None:
                text = short_decimal_text(value)
            if text is None:
                text = exact_decimal_text(value)
            if text is not None:
                return text, False
            if self.style == "exact":
                return f"{mpz_text(value.numerator)}/{mpz_text(value.denominator)}", False
        text, exact = nearest_double_text(value)
        return text, not exact


def mpz_text(value: Any) -> str:
    """Decimal digits of an integer of any size (gmpy2 has no int-to-str digit limit)."""
    return str(gmpy2.mpz(value).digits(10))


def short_decimal_text(value: Rational) -> str | None:
    """:func:`exact_decimal_text` of a non-integer ``value`` of magnitude 0.1 to 10^15
    that is exactly the shortest text of its nearest double (a decimal read from a file:
    ``0.8444218515250481``), found without factoring its denominator; else None.  In that
    range the plain form is the shorter one and a shortest double text has no trailing
    zero, so this is the text :func:`exact_decimal_text` gives."""
    if value.denominator == 1:
        return None
    try:
        double = to_float(value)
    except OverflowError:
        return None
    if not 0.1 <= abs(double) < 1e15:
        return None
    text = repr(double)
    if "e" in text or gmpy2.mpq(text) != value:
        return None
    return text


def exact_decimal_text(value: Rational) -> str | None:
    """The exact decimal text a writer uses (:func:`~geomexact.kernel.numbers.
    exact_decimal`, preferring the plain form unless the exponent saves a run of zeros),
    or None when the expansion does not terminate."""
    return exact_decimal(value, plain_within=_ZEROS_WORTH_AN_EXPONENT)


def nearest_double_text(value: Rational) -> tuple[str, bool]:
    """(text, exact): the shortest text of the double nearest to ``value``; for a value
    beyond the normal doubles (overflow, or a nonzero value below 2^-1022, where a double
    keeps fewer digits or none) the value rounded to 17 significant digits instead.
    ``exact`` tells whether the text is ``value`` exactly."""
    try:
        double = to_float(value)
    except OverflowError:
        double = math.inf
    if value == 0 or _SMALLEST_NORMAL <= abs(double) < math.inf:
        if double.is_integer() and abs(double) <= _EXACT_INTEGER_LIMIT:
            text = str(int(double))
        else:
            text = repr(double)
        # exact when the text itself is the value (``1.5e-30`` is, its double is not)
        return text, parse_rational(text) == value
    return _significant_digits_text(value)


def _significant_digits_text(value: Rational) -> tuple[str, bool]:
    """``value`` rounded half-even to 17 significant digits, as decimal text."""
    magnitude = abs(gmpy2.mpq(value))
    # 10^power <= magnitude < 10^(power + 1); log10(2) < 0.30103 makes the start a lower bound
    power = (floor_log2(magnitude) * 30103) // 100000 - 1
    while gmpy2.mpq(10) ** (power + 1) <= magnitude:
        power += 1
    scale = _ROUNDED_DIGITS - 1 - power
    scaled = magnitude * gmpy2.mpq(10) ** scale
    floor = scaled.numerator // scaled.denominator
    remainder = scaled - floor
    digits_value = floor + 1 if remainder * 2 > 1 or (remainder * 2 == 1 and floor % 2) else floor
    rounded = gmpy2.mpq(-digits_value if value < 0 else digits_value) / gmpy2.mpq(10) ** scale
    text = exact_decimal_text(rounded)
    assert text is not None  # digits * 10^-scale always terminates
    return text, remainder == 0


_PART_NOUNS = {
    "vertex markers": ("nonzero vertex marker", "nonzero vertex markers"),
    "vertex attributes": ("vertex with attributes", "vertices with attributes"),
    "triangle attributes": ("triangle with attributes (regions)",
                            "triangles with attributes (regions)"),
    "segments": ("segment", "segments"),
    "holes": ("hole", "holes"),
    "regions": ("region", "regions"),
}


def written_value(value: Value, kind: type[_Written], format_name: str) -> _Written:
    """``value``, when it is a ``kind``: the one kind of value the format ``format_name``
    writes; UnsupportedValueError (a ``TypeError``) otherwise."""
    if not isinstance(value, kind):
        raise UnsupportedValueError(
            f"the {format_name} format writes a {kind.__name__}, not a {type(value).__name__}"
        )
    return value


def dropped_parts(value: Value, holds: Collection[str]) -> tuple[str, ...]:
    """What of ``value`` a format that holds only the parts named in ``holds`` cannot
    write: one phrase per nonempty part (``"12 segments"``, ``"3 nonzero vertex
    markers"``).  The parts are the keys of ``_PART_NOUNS``."""
    counts: dict[str, int] = {}
    if isinstance(value, Mesh2):
        counts["vertex markers"] = sum(1 for marker in value.vertex_markers.values() if marker)
        counts["vertex attributes"] = len(value.vertex_attributes)
        counts["triangle attributes"] = len(value.triangle_attributes)
        counts["segments"] = len(value.segments)
    elif isinstance(value, PSLG):
        counts["vertex markers"] = sum(1 for marker in value.vertex_markers if marker)
        counts["vertex attributes"] = sum(1 for row in value.vertex_attributes if row)
        counts["segments"] = len(value.segments)
        counts["holes"] = len(value.holes)
        counts["regions"] = len(value.regions)
    return tuple(
        f"{count} {_PART_NOUNS[part][count != 1]}"
        for part, count in counts.items()
        if count and part not in holds
    )


def write_files(
    files: Sequence[tuple[Path, str | Iterable[str]]],
    *,
    overwrite: bool,
    numbers: NumberText | None = None,
    dropped: tuple[str, ...] = (),
    members: Sequence[Path] = (),
) -> WriteReport:
    """Write each (path, text), the text whole or in chunks written as they come, as one
    set: every file appears or none does (:func:`~geomexact.io.files.output_set`).  When
    not ``overwrite``, refuse (OverwriteError) before writing anything if any target, or
    any other of the format's ``members`` (e.g. the ``.poly`` of a Triangle mesh), exists;
    with ``overwrite`` a member not written again is removed with the set, so no stale
    file is read with the new ones.  Files of more than one are stamped as one set
    (:func:`file_set_stamp`).  The report counts what ``numbers`` rounded and lists what
    was ``dropped``."""
    written = [path for path, _ in files]
    if not overwrite:
        for path in (*written, *members):
            if path.exists():
                raise OverwriteError(str(path))
    with output_set() as outputs:
        digests = []
        for path, text in files:
            chunks = (text,) if isinstance(text, str) else text
            digests.append(outputs.stage(path, (chunk.encode("utf-8") for chunk in chunks),
                                         overwrite=overwrite))
        if len(files) > 1:
            stamp = file_set_stamp(digests, written)
            for path in written:
                outputs.append(path, stamp.encode("utf-8"))
        for member in members:
            if member not in written:
                outputs.remove_with_commit(member)
    return WriteReport(
        tuple(written), numbers.rounded if numbers is not None else 0, dropped
    )


FILE_SET_MARK = "# geomexact file set "
"""How the last line of each file of a set written together starts (:func:`write_files`)."""


def file_set_stamp(digests: Sequence[str], paths: Sequence[Path]) -> str:
    """The last line written into each file of a set: :data:`FILE_SET_MARK`, then an
    identifier made from the files' contents and their extensions (so the same set is the
    same bytes, whatever its name), then ``(N files)``."""
    parts = [f"{path.suffix}:{digest}" for path, digest in zip(paths, digests, strict=True)]
    identifier = hashlib.blake2b(" ".join(parts).encode("utf-8"), digest_size=12).hexdigest()
    return f"{FILE_SET_MARK}{identifier} ({len(paths)} files)\n"


_TAIL_BYTES = 1024


def _file_set_identifier(path: Path) -> str | None:
    """The set identifier stamped on the last line of ``path``, or None (also for a file
    that is not a regular one, which its reader then refuses: a FIFO would block here)."""
    try:
        with open_regular(path) as handle:
            handle.seek(0, os.SEEK_END)
            size = handle.tell()
            handle.seek(max(0, size - _TAIL_BYTES))
            tail = handle.read()
    except (OSError, FormatError):
        return None
    lines = tail.rstrip(b"\n").rsplit(b"\n", 1)
    last = lines[-1].decode("utf-8", "replace")
    if not last.startswith(FILE_SET_MARK):
        return None
    return last[len(FILE_SET_MARK):].split(" ", 1)[0].strip()


def check_file_set(paths: Sequence[Path]) -> None:
    """Refuse (:class:`FormatError` naming the files) files of one mesh that were not
    written together: the existing ``paths`` that carry a file-set stamp must all carry
    the same one.  A write interrupted between its renames, or files mixed from two
    writes, would otherwise read as a valid, wrong mesh.  A file without a stamp (written
    by another program, or edited by hand) is not compared."""
    stamped = [(path, stamp) for path in paths if path.exists()
               if (stamp := _file_set_identifier(path)) is not None]
    for path, stamp in stamped[1:]:
        first, identifier = stamped[0]
        if stamp != identifier:
            raise FormatError(
                str(path), None,
                f"{first.name} and {path.name} come from different writes (file sets "
                f"{identifier} and {stamp}): a write was interrupted or the files of two "
                "meshes were mixed; write the mesh again (or, to combine them on purpose, "
                f"delete the last line '{FILE_SET_MARK}...' of each)")


def uniform_attributes(
    tables: Sequence[Attributes | None], what: str
) -> tuple[int, list[Attributes]]:
    """(count, rows) for a file column block: every row padded to the common length with
    zeros when missing; a ValueError when two rows have different lengths."""
    lengths = {len(row) for row in tables if row}
    if len(lengths) > 1:
        raise PreconditionError(
            "write", f"{what} attributes have different lengths {sorted(lengths)}"
        )
    count = lengths.pop() if lengths else 0
    rows = [tuple(row) if row else (ZERO,) * count for row in tables]
    return count, rows


def file_stem(path: Path, extension: str) -> Path:
    """``path`` without ``extension`` when it ends with it, else ``path`` itself (so
    ``x.1.ele`` and ``x.1`` both name the stem ``x.1``)."""
    if path.name.lower().endswith(extension) and len(path.name) > len(extension):
        return path.with_name(path.name[: -len(extension)])
    return path


def file_set_stem(path: Path, extensions: Iterable[str]) -> Path:
    """The stem of a file set named by any of its files (the first of ``extensions`` that
    ``path`` ends with is cut off) or by the stem itself."""
    for extension in extensions:
        stem = file_stem(path, extension)
        if stem != path:
            return stem
    return path


def with_extension(stem: Path, extension: str) -> Path:
    """``stem`` + ``extension`` (appended, never replacing a dotted part of the stem)."""
    return stem.with_name(stem.name + extension)
