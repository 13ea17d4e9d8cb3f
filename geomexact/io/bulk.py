"""Whole tables at once, for the readers and writers of the line formats (Triangle, OFF,
TetGen): files at disk speed (issue 15, item 2; ``specs/formats/registry.md``).

Writing: a mesh's triangles and their neighbours as sorted numpy tables
(:func:`triangle_array`, :func:`neighbour_array`) and rows formatted by one ``%`` over a
repeated template (:func:`rows_text`); the numbers themselves through
:class:`~geomexact.io.registry.NumberText`, which formats each distinct value once.

Reading: :func:`plain_table` splits a whole file into tokens in one pass and counts the
tokens of every line with numpy, so a reader can take a section of ``count`` lines of
``width`` fields as one flat list when the section is regular; :func:`integer_column`
and :func:`number_column` convert columns in bulk (plain integers and decimals only; a
token of any other form makes them return None).  Every fast path is all or nothing: when
anything is unusual (a comment inside a section, a short line, ``+3``, a bad index) it
returns None and the reader reads the file line by line as before, so what it accepts and
every error message (file, line, problem) stay exactly those of the line-by-line reader.
"""

from __future__ import annotations

import itertools
import re
from array import array
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import attrs
import gmpy2
import numpy as np
import numpy.typing as npt

from geomexact.errors import RationalParseError
from geomexact.kernel.numbers import Rational, parse_rational
from geomexact.kernel.points import nearest_double
from geomexact.mesh2d.snapshot import Mesh2

IntArray = npt.NDArray[np.int64]

__all__ = [
    "PlainTable",
    "integer_column",
    "neighbour_array",
    "number_column",
    "numbered",
    "plain_table",
    "rows_text",
    "triangle_array",
]


# -----------------------------------------------------------------------------------------
# writing
# -----------------------------------------------------------------------------------------
def triangle_array(mesh: Mesh2) -> IntArray:
    """The triangles of ``mesh``, canonical and sorted (``mesh.triangles()``), as a
    (T x 3) int64 array: one pass over the half-edge table, sorted by numpy (twice as
    fast as sorting the tuples)."""
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


@attrs.frozen(slots=True)
class PlainTable:
    """A whole ASCII file as tokens: ``tokens`` (every token of the file, in order);
    ``lines`` (the 1-based number of each data line, the lines with a token: blank lines
    and comments dropped as :func:`~geomexact.io.registry.token_lines` drops them);
    ``widths`` (the token count of each data line) and ``starts`` (the index in
    ``tokens`` of each data line's first token)."""

    tokens: list[str]
    lines: IntArray
    widths: IntArray
    starts: IntArray

    def section(self, line: int, count: int, width: int) -> tuple[list[str], list[int]] | None:
        """The tokens of data lines ``line .. line + count - 1`` (0-based indices into
        the data lines) when each has exactly ``width`` tokens, with their line numbers;
        None when the file has fewer lines or one of them has another width."""
        if count == 0:
            return [], []
        if line + count > len(self.widths) or not np.all(
            self.widths[line : line + count] == width
        ):
            return None
        start = int(self.starts[line])
        return (
            self.tokens[start : start + count * width],
            self.lines[line : line + count].tolist(),
        )


def plain_table(path: Path) -> PlainTable | None:
    """The file ``path`` as a :class:`PlainTable`, or None when it is not plain ASCII text
    (a byte-order mark, non-ASCII bytes, gzip data: the line reader handles those and
    names the line of a bad byte) or cannot be read (the line reader reports why)."""
    try:
        data = path.read_bytes()
    except OSError:
        return None
    if not data.isascii():
        return None
    if b"#" in data:
        data = _COMMENT.sub(b"", data)
    raw = np.frombuffer(data, dtype=np.uint8)
    space = _SPACE[raw]
    newline = raw == 10
    # a token starts at a non-space byte that follows a space or starts the text
    start = ~space
    start[1:] &= space[:-1]
    token_at = np.flatnonzero(start)
    line_of_token = np.searchsorted(np.flatnonzero(newline), token_at, side="right")
    tokens = data.decode("ascii").split()
    if len(tokens) != len(token_at):  # pragma: no cover - the two splits agree on ASCII
        return None
    lines, starts, widths = np.unique(line_of_token, return_index=True, return_counts=True)
    return PlainTable(tokens, lines.astype(np.int64) + 1, widths.astype(np.int64),
                      starts.astype(np.int64))


_PLAIN_INTEGERS = re.compile(r"(?:-?[0-9]{1,18} )*")
# what gmpy2's parser reads as parse_rational does (it refuses "+3" and "-.5"); an exponent
# of at most 6 digits is below parse_rational's limit
_PLAIN_NUMBER = re.compile(r"-?[0-9]+(?:\.[0-9]*)?(?:[eE][-+]?[0-9]{1,6})?")
_GMPY_SAFE_LENGTH = 4000


def integer_column(tokens: Sequence[str]) -> IntArray | None:
    """``tokens`` as int64 when every one is a plain integer (``-?digits``, at most 18
    digits), else None."""
    joined = " ".join(tokens) + " "
    if not _PLAIN_INTEGERS.fullmatch(joined):
        return None
    return np.array(list(map(int, tokens)), dtype=np.int64)


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
