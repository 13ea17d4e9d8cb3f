"""Whole tables at once, for the readers and writers of the line formats (Triangle, OFF,
TetGen): files at disk speed (issue 15, item 2; ``specs/formats/registry.md``).

Writing: a mesh's triangles and their neighbours as sorted numpy tables
(:func:`triangle_array`, :func:`neighbour_array`) and rows formatted by one ``%`` over a
repeated template (:func:`rows_text`); the numbers themselves through
:class:`~geomexact.io.registry.NumberText`, which formats each distinct value once.

Reading: :class:`PlainLines` splits a file into tokens a block at a time and counts the
tokens of every line with numpy, so a reader takes a section of ``count`` lines of
``width`` fields as flat lists of tokens when the section is regular; :func:`integer_column`
and :func:`number_column` convert columns in bulk (plain integers and decimals only; a
token of any other form makes them return None).  Every fast path is all or nothing: when
anything is unusual (a comment inside a section, a short line, ``+3``, a bad index) it
returns None and the reader reads the file line by line as before, so what it accepts and
every error message (file, line, problem) stay exactly those of the line-by-line reader.
"""

from __future__ import annotations

import functools
import itertools
import re
from array import array
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any, ParamSpec, TypeVar

import gmpy2
import immutables
import numpy as np
import numpy.typing as npt

from geomexact.errors import FormatError, RationalParseError
from geomexact.io.files import open_regular
from geomexact.kernel import digest as _digest
from geomexact.kernel.array_filters import orient2d_signs, point_doubles
from geomexact.kernel.numbers import Rational, parse_rational
from geomexact.kernel.points import Point2, nearest_double
from geomexact.kernel.predicates2d import orient2d
from geomexact.mesh2d.snapshot import Attributes, Mesh2, TableSource

IntArray = npt.NDArray[np.int64]
_Args = ParamSpec("_Args")
_Read = TypeVar("_Read")
Doubles = tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]
"""The doubles ``fx``, ``fy`` of a file's points, computed once per file."""

__all__ = [
    "Doubles",
    "NotPlain",
    "PlainLines",
    "bulk_mesh2",
    "integer_column",
    "neighbour_array",
    "number_column",
    "numbered",
    "orientation_signs",
    "row_chunks",
    "rows_text",
    "triangle_array",
]


# -----------------------------------------------------------------------------------------
# writing
# -----------------------------------------------------------------------------------------
def triangle_array(mesh: Mesh2) -> IntArray:
    """The triangles of ``mesh``, canonical and sorted (``mesh.triangles()``), as a
    (T x 3) int64 array: one pass over the half-edge table, sorted by numpy (twice as
    fast as sorting the tuples; from a kernel's arrays when the tables are not built)."""
    source = mesh.source
    if source is not None:
        rows = source.triangle_rows()
    else:
        flat = array("q", itertools.chain.from_iterable(mesh.iter_triangles()))
        rows = np.frombuffer(flat, dtype=np.int64).reshape(-1, 3)
    return rows[np.lexsort(rows.T[::-1])]


def neighbour_array(triangles: IntArray) -> IntArray:
    """For each triangle (a, b, c) of a consistently oriented table, the indices of the
    triangles across the edges opposite a, b and c, -1 for none:
    :func:`~geomexact.io.registry.expected_neighbours`, vectorised."""
    count = len(triangles)
    if not count:
        return np.zeros((0, 3), dtype=np.int64)
    t = triangles.astype(np.uint64)
    a, b, c = t[:, 0], t[:, 1], t[:, 2]
    shift = np.uint64(32)
    keys = np.concatenate(((a << shift) | b, (b << shift) | c, (c << shift) | a))
    owners = np.tile(np.arange(count, dtype=np.int64), 3)
    order = np.argsort(keys, kind="stable")
    keys, owners = keys[order], owners[order]
    wanted = np.column_stack(((c << shift) | b, (a << shift) | c, (b << shift) | a))
    at = np.searchsorted(keys, wanted)
    clipped = np.minimum(at, len(keys) - 1)
    found = keys[clipped] == wanted
    return np.where(found, owners[clipped], -1)


def rows_text(template: str, count: int, values: Sequence[Any]) -> str:
    """``count`` rows of ``template`` (one row, ending in a newline) filled from the flat
    ``values``, by one ``%`` formatting: each row is what ``template % row`` gives."""
    return (template * count) % tuple(values)


def row_chunks(template: str, rows: IntArray, *, numbered: bool = False,
               size: int = 1 << 16) -> Iterator[str]:
    """The text of the (R x k) integer ``rows``, each by ``template`` (one row, ending in
    a newline), preceded by its index (0, 1, …) when ``numbered``: what
    :func:`rows_text` gives, in chunks of ``size`` rows, so that a large table is never
    held as Python ints or text whole."""
    for begin in range(0, len(rows), size):
        block = rows[begin : begin + size]
        if numbered:
            block = np.column_stack(
                (np.arange(begin, begin + len(block), dtype=np.int64), block)
            )
        yield (template * len(block)) % tuple(block.ravel().tolist())


def numbered(flat: list[Any], width: int) -> list[Any]:
    """The rows of ``width`` values of ``flat``, each preceded by its index (0, 1, …),
    flat again: the rows of a numbered table for :func:`rows_text`."""
    count = len(flat) // width
    out: list[Any] = [0] * (count * (width + 1))
    out[0 :: width + 1] = range(count)
    for column in range(width):
        out[column + 1 :: width + 1] = flat[column::width]
    return out


# -----------------------------------------------------------------------------------------
# reading
# -----------------------------------------------------------------------------------------
_SPACE = np.zeros(256, dtype=bool)
for _byte in b" \t\n\r\x0b\x0c\x1c\x1d\x1e\x1f":  # what str.split() splits ASCII text on
    _SPACE[_byte] = True
_COMMENT = re.compile(rb"#[^\n]*")


class NotPlain(Exception):
    """Raised inside a fast path: the file is not plain, the line reader takes over."""


BLOCK = 1 << 15
"""Bytes read at a time by :class:`PlainLines`: a bad line near the start of a large
file is found after one block, in bounded memory, as the line reader finds it."""

PLAIN_LINE_LIMIT = 1 << 20
"""The longest line (bytes) a fast path takes: the lines of a plain table are short, and
a longer one (all of a file on one line) is left to the line reader, which refuses it
beyond :data:`~geomexact.io.files.LINE_LIMIT`."""


class PlainLines:
    """A plain ASCII file read in blocks of whole lines, each block split into tokens in
    one pass, the tokens of its lines counted with numpy; a context manager (the file is
    closed on leaving).  Anything a fast path does not handle raises :class:`NotPlain`: a
    byte-order mark or any non-ASCII byte (the line reader names the line of a bad
    byte), a file that cannot be opened or is not a regular file, a line longer than
    :data:`PLAIN_LINE_LIMIT`, a section whose lines do not all have the announced number
    of tokens, a file that ends early.  Comments and blank lines are
    dropped as :func:`~geomexact.io.registry.token_lines` drops them."""

    def __init__(self, path: Path) -> None:
        try:
            self._handle = open_regular(path)
        except FormatError:
            raise NotPlain from None
        self._newlines = 0  # newlines before the current block
        self._carry = b""
        self._tokens: list[str] = []
        self._lines: list[int] = []
        self._widths: list[int] = []
        self._starts: list[int] = []
        self._at = 0  # the next data line of the block

    def __enter__(self) -> PlainLines:
        return self

    def __exit__(self, *exc: object) -> None:
        self._handle.close()

    def _load(self) -> bool:
        """Read the next block of whole lines; False at the end of the file.  Linear in
        the length of a long line: its pieces are joined once, not one onto the other."""
        parts = [self._carry]
        size = len(self._carry)  # the carry holds no newline
        while True:
            more = self._handle.read(BLOCK)
            parts.append(more)
            size += len(more)
            if not more or b"\n" in more:
                break
            if size > PLAIN_LINE_LIMIT:
                raise NotPlain
        data = b"".join(parts)
        if not data:
            return False
        cut = data.rfind(b"\n") + 1 or len(data)
        block, self._carry = data[:cut], data[cut:]
        if not block.isascii():
            raise NotPlain
        if b"#" in block:
            block = _COMMENT.sub(b"", block)
        raw = np.frombuffer(block, dtype=np.uint8)
        space = _SPACE[raw]
        start = ~space
        start[1:] &= space[:-1]  # a token starts at a non-space byte after a space
        token_at = np.flatnonzero(start)
        line_of_token = np.searchsorted(np.flatnonzero(raw == 10), token_at, side="right")
        self._tokens = block.decode("ascii").split()
        if len(self._tokens) != len(token_at):  # pragma: no cover - both split ASCII alike
            raise NotPlain
        lines, starts, widths = np.unique(line_of_token, return_index=True,
                                          return_counts=True)
        self._lines = (lines + (self._newlines + 1)).tolist()
        self._starts = starts.tolist()
        self._widths = widths.tolist()
        self._newlines += block.count(b"\n")
        self._at = 0
        return True

    def _available(self) -> int:
        """Data lines left in the block, reading blocks until there are some (0: the
        file ends)."""
        while self._at >= len(self._widths):
            if not self._load():
                return 0
        return len(self._widths) - self._at

    def next_line(self) -> tuple[list[str], int]:
        """The tokens and number of the next data line."""
        if not self._available():
            raise NotPlain
        at = self._at
        start = self._starts[at]
        self._at += 1
        return self._tokens[start : start + self._widths[at]], self._lines[at]

    def chunks(self, count: int, width: int) -> Iterator[tuple[list[str], list[int]]]:
        """The next ``count`` data lines, each of ``width`` tokens, as (their tokens,
        their numbers), a block at a time."""
        left = count
        while left:
            available = self._available()
            if not available:
                raise NotPlain
            taken = min(available, left)
            at = self._at
            widths = self._widths[at : at + taken]
            if widths.count(width) != taken:
                raise NotPlain
            start = self._starts[at]
            self._at += taken
            left -= taken
            yield (self._tokens[start : start + taken * width],
                   self._lines[at : at + taken])

    def at_end(self) -> bool:
        """True when no data line is left."""
        return not self._available()


# what gmpy2's parser reads as parse_rational does (it refuses "+3" and "-.5"); an exponent
# of at most 6 digits is below parse_rational's limit
_PLAIN_NUMBER = re.compile(r"-?[0-9]+(?:\.[0-9]*)?(?:[eE][-+]?[0-9]{1,6})?")
_GMPY_SAFE_LENGTH = 4000


def integer_column(tokens: Sequence[str]) -> IntArray | None:
    """``tokens`` as int64 when each is an integer as
    :func:`~geomexact.io.registry.parse_int` reads it (``int()`` of ASCII text) and fits
    in 64 bits, else None."""
    try:
        return np.array(list(map(int, tokens)), dtype=np.int64)
    except (ValueError, OverflowError):
        return None


def number_column(
    tokens: Sequence[str], cache: dict[str, tuple[Rational, float]]
) -> tuple[list[Rational], list[float]] | None:
    """The exact values of ``tokens`` and their nearest doubles (a point's ``fx``), each
    distinct token parsed once (``cache``: token -> (value, double), shared by the columns
    of one file); None when a token is not a number
    (:func:`~geomexact.kernel.numbers.parse_rational` refuses it).  Plain decimals (the
    common case) are read by gmpy2's own parser, the rest by ``parse_rational``: the same
    exact value."""
    get = cache.get
    for token in set(tokens):
        if get(token) is not None:
            continue
        value: Rational
        if len(token) < _GMPY_SAFE_LENGTH and _PLAIN_NUMBER.fullmatch(token):
            value = gmpy2.mpq(token)
        else:
            try:
                value = parse_rational(token)
            except RationalParseError:
                return None
        cache[token] = (value, nearest_double(value))
    pairs = [cache[token] for token in tokens]
    return [pair[0] for pair in pairs], [pair[1] for pair in pairs]


def orientation_signs(
    points: Sequence[Point2], triangles: IntArray, doubles: Doubles | None = None
) -> IntArray:
    """The exact ``orient2d`` sign (1, -1 or 0) of each row (a, b, c) of ``triangles``:
    the certified numpy filter (:func:`~geomexact.kernel.array_filters.orient2d_signs`),
    the exact predicate for the rows it leaves undecided.  ``doubles``: the points'
    :func:`~geomexact.kernel.array_filters.point_doubles`, when the caller has them."""
    fx, fy = doubles if doubles is not None else point_doubles(points)
    signs = orient2d_signs(fx, fy, triangles[:, 0], triangles[:, 1], triangles[:, 2])
    for row in np.flatnonzero(signs == 0).tolist():
        a, b, c = triangles[row].tolist()
        signs[row] = int(orient2d(points[a], points[b], points[c]))
    return signs.astype(np.int64)


def bulk_mesh2(
    points: Sequence[Point2],
    triangles: IntArray,
    vertex_markers: Sequence[int] | None = None,
    vertex_attributes: Sequence[Attributes] | None = None,
) -> Mesh2 | None:
    """The :class:`Mesh2` that adding ``points`` (with their markers and attributes) and
    then the counter-clockwise ``triangles`` in order to an empty transient builds, the
    same tables and digest, made in bulk; None when two triangles lie on the same side of
    an edge (the transient's error, which the caller then reproduces with it)."""
    count = len(triangles)
    flat = np.ascontiguousarray(triangles, dtype=np.int64).ravel()
    # the half-edges (a, b, c), (b, c, a), (c, a, b) of each triangle, in order
    rows = np.column_stack((flat, triangles[:, [1, 2, 0]].ravel(),
                            triangles[:, [2, 0, 1]].ravel())).astype(np.int64)
    edge_keys = np.sort(
        (rows[:, 0].astype(np.uint64) << np.uint64(32)) | rows[:, 1].astype(np.uint64))
    if bool(np.any(edge_keys[1:] == edge_keys[:-1])):  # (sorting: numpy's unique hashes)
        return None
    # the outgoing hint of each vertex: its last edge out, as a dict filled in order keeps
    hints = np.full(len(points), -1, dtype=np.int64)
    reversed_u = rows[::-1, 0]
    vertices_seen, last = np.unique(reversed_u, return_index=True)
    hints[vertices_seen] = rows[::-1, 1][last]
    u = flat.tolist()
    vertex_hash, combine, attribute_hash = _digest.vertex_hash, _digest.combine, (
        _digest.attribute_hash)
    total = 0
    for index, point in enumerate(points):
        total += vertex_hash(index, point[:2])
    markers: dict[int, int] = {}
    if vertex_markers is not None:
        for index, marker in enumerate(vertex_markers):
            if marker:
                markers[index] = marker
                total += attribute_hash("vm", (index,), (marker,))
    attributes: dict[int, Attributes] = {}
    if vertex_attributes is not None:
        for index, row in enumerate(vertex_attributes):
            if row:
                attributes[index] = tuple(row)
                total += attribute_hash("va", (index,), row)
    if count:
        _digest.vertex_key(int(flat.max()))
    keys = _digest.VERTEX_KEYS
    m0, m1, m2 = _digest.TRIANGLE_MULTIPLIERS
    final, mask = _digest.FINAL_MULTIPLIER, _digest.MODULUS - 1
    for a, b, c in zip(u[0::3], u[1::3], u[2::3], strict=True):
        if not (a < b and a < c):
            a, b, c = (b, c, a) if b < c else (c, a, b)
        x = (keys[a] * m0 + keys[b] * m1 + keys[c] * m2) & mask
        x ^= x >> 61
        total += (x * final) & mask
    rows.setflags(write=False)
    hints.setflags(write=False)
    # the persistent tables are built on first use, from these arrays (a command that
    # refines and writes the mesh never needs them)
    return Mesh2(
        vertices=None,
        halfedges=None,
        outgoing=None,
        source=TableSource(list(points), rows, hints),
        segments=immutables.Map(),
        vertex_markers=immutables.Map(markers),
        vertex_attributes=immutables.Map(attributes),
        triangle_attributes=immutables.Map(),
        triangle_count=count,
        digest=combine(0, total),
    )


def numbered_corners(
    rows: IntArray, first: int, done: int, base: int, vertex_count: int
) -> IntArray | None:
    """The 0-based corners of ``rows`` (a number, then vertex numbers, each), the rows
    that follow the first ``done`` of a table numbered from ``first``; None unless
    ``first`` is 0 or 1, the rows are numbered on from there and every corner is one of
    the ``vertex_count`` vertices numbered from ``base``."""
    start = first + done
    corners = rows[:, 1:] - base
    if (
        first not in (0, 1)
        or not np.array_equal(rows[:, 0], np.arange(start, start + len(rows)))
        or int(corners.min()) < 0 or int(corners.max()) >= vertex_count
    ):
        return None
    return corners


def oriented_rows(
    points: Sequence[Point2], rows: IntArray, doubles: Doubles | None = None
) -> tuple[IntArray, int] | None:
    """``rows`` (0-based triangles, indices in range) made counter-clockwise, with the
    number reversed (0, or all of them when all are clockwise); None when a triangle
    repeats a vertex or is degenerate, or the orientations are mixed (the line reader
    names the triangle)."""
    a, b, c = rows[:, 0], rows[:, 1], rows[:, 2]
    if bool(np.any((a == b) | (a == c) | (b == c))):
        return None
    signs = orientation_signs(points, rows, doubles)
    if bool(np.all(signs == 1)):
        return rows, 0
    if bool(np.all(signs == -1)):
        return rows[:, [0, 2, 1]], len(rows)
    return None


def plain_first(
    plain: Callable[_Args, _Read | None],
) -> Callable[[Callable[_Args, _Read]], Callable[_Args, _Read]]:
    """A line reader that first tries ``plain``, the bulk reader of a plain file taking
    the same arguments: ``plain``'s result when it gives one, else the line reader's
    (which reads any file, and names the error in one it cannot)."""

    def decorate(read: Callable[_Args, _Read]) -> Callable[_Args, _Read]:
        @functools.wraps(read)
        def reader(*args: _Args.args, **kwargs: _Args.kwargs) -> _Read:
            found = plain(*args, **kwargs)
            return read(*args, **kwargs) if found is None else found

        return reader

    return decorate


class OrientedChunks:
    """The triangles of a plain file's section, added a chunk at a time (:meth:`add`),
    all of one orientation: ``reversed_count`` of them are clockwise (0 or all)."""

    def __init__(self, points: Sequence[Point2]) -> None:
        """``points``: the file's points, all read before the first :meth:`add`."""
        self._points = points
        self._doubles: Doubles | None = None
        self._parts: list[IntArray] = []
        self.reversed_count = 0
        self.lines: list[int | None] = []
        """The line number of each triangle :meth:`read_last_section` added."""

    @property
    def empty(self) -> bool:
        """No chunk added yet."""
        return not self._parts

    def add(self, corners: IntArray) -> bool:
        """Add ``corners`` (0-based triangles, indices in range); False when a triangle
        repeats a vertex or is degenerate, or the orientations are mixed, within the chunk
        or with the chunks before (the line reader names the triangle)."""
        if self._doubles is None:
            self._doubles = point_doubles(self._points)
        oriented = oriented_rows(self._points, corners, self._doubles)
        if oriented is None or (self._parts and bool(oriented[1]) != bool(self.reversed_count)):
            return False
        self.reversed_count += oriented[1]
        self._parts.append(corners)
        return True

    def read_last_section(self, lines: PlainLines, count: int,
                          corners_of: Callable[[IntArray], IntArray | None]) -> bool:
        """Read the last ``count`` lines of ``lines``, four integers each (a number, then
        three vertices), a chunk at a time: ``corners_of`` makes a chunk's rows (n x 4)
        0-based triangles, or None when they are not plain; each chunk is :meth:`add`-ed
        and its line numbers kept in :attr:`lines`.  False as soon as a chunk does not
        parse, is not plain or cannot be added, or when the file goes on after them."""
        for tokens, numbers in lines.chunks(count, 4):
            values = integer_column(tokens)
            if values is None:
                return False
            corners = corners_of(values.reshape(-1, 4))
            if corners is None or not self.add(corners):
                return False  # (add: degenerate, or mixed orientations)
            self.lines.extend(numbers)
        return lines.at_end()

    def tables(self) -> tuple[IntArray, IntArray]:
        """The triangles added, in order: as they are in the file, and made
        counter-clockwise (each T x 3)."""
        corners = (np.concatenate(self._parts) if self._parts
                   else np.zeros((0, 3), dtype=np.int64))
        return corners, corners[:, [0, 2, 1]] if self.reversed_count else corners


def triangle_tuples(rows: IntArray) -> list[tuple[int, int, int]]:
    """The rows of a (T x 3) table as tuples."""
    return list(zip(rows[:, 0].tolist(), rows[:, 1].tolist(), rows[:, 2].tolist(),
                    strict=True))
