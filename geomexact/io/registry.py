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

import math
from collections.abc import Callable, Collection, Sequence
from pathlib import Path
from typing import Any, Literal, Protocol, TypeAlias

import attrs
import gmpy2

from geomexact.errors import FormatError, OverwriteError, PreconditionError, RationalParseError
from geomexact.io.files import write_text_atomic
from geomexact.kernel.numbers import ZERO, Rational, floor_log2, parse_rational, to_float
from geomexact.kernel.points import Point2
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates2d import orient2d
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Attributes, Mesh2, empty_mesh
from geomexact.mesh2d.transient import Transient2

Value: TypeAlias = Mesh2 | PSLG | PolygonMesh
"""What a reader returns and a writer accepts."""

Tokens: TypeAlias = list[str]
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
def data_lines(text: str) -> list[NumberedLine]:
    """The non-blank lines of ``text`` as (1-based line number, tokens), with everything
    from a ``#`` to the end of its line removed.  Lines are split on ``\\n`` only (so line
    numbers agree with ``read_text``'s and with editors'); tokens on any whitespace."""
    result: list[NumberedLine] = []
    text = text.removeprefix("\ufeff")  # a byte-order mark is not data
    for number, line in enumerate(text.split("\n"), start=1):
        if "#" in line:
            line = line[: line.index("#")]
        tokens = line.split()
        if tokens:
            result.append((number, tokens))
    return result


class Lines:
    """A cursor over numbered lines of one file; running out is a :class:`FormatError`
    saying what was expected (a truncated file)."""

    __slots__ = ("_index", "_lines", "last_line", "path")

    def __init__(self, path: str, lines: list[NumberedLine]) -> None:
        self.path = path
        self._lines = lines
        self._index = 0
        self.last_line: int | None = lines[-1][0] if lines else None

    def next(self, what: str) -> NumberedLine:
        """The next line, or a FormatError "file ends before <what>"."""
        if self._index >= len(self._lines):
            raise FormatError(self.path, self.last_line, f"the file ends before {what}")
        line = self._lines[self._index]
        self._index += 1
        return line

    def at_end(self) -> bool:
        """True when every line was consumed."""
        return self._index >= len(self._lines)

    def rest(self) -> list[NumberedLine]:
        """The lines not consumed yet (and consume them)."""
        remaining = self._lines[self._index :]
        self._index = len(self._lines)
        return remaining

    def expect_end(self, what: str) -> None:
        """FormatError when lines remain after the last section ``what``."""
        if not self.at_end():
            number, tokens = self._lines[self._index]
            raise FormatError(
                self.path, number, f"unexpected data after {what}: {' '.join(tokens)!r}"
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
        pass
    raise FormatError(path, line, f"{what}: {token!r} is not an integer")


def parse_number(path: str, line: int, token: str, what: str) -> Rational:
    """``token`` parsed exactly (:func:`geomexact.kernel.numbers.parse_rational`), or a FormatError
    embedding the parser's message."""
    try:
        return parse_rational(token)
    except RationalParseError as error:
        raise FormatError(path, line, f"{what}: {error}") from error


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
            f"{what} needs {least} fields, found {len(tokens)}: {' '.join(tokens)!r}",
        )


def expect_exact_fields(path: str, line: int, tokens: Tokens, count: int, what: str) -> None:
    """FormatError when ``tokens`` does not have exactly ``count`` fields."""
    if len(tokens) != count:
        raise FormatError(
            path,
            line,
            f"{what} needs {count} fields, found {len(tokens)}: {' '.join(tokens)!r}",
        )


def expect_field_range(
    path: str, line: int, tokens: Tokens, low: int, high: int, what: str
) -> None:
    """FormatError naming ``what`` (the record's expected form) when ``tokens`` has fewer
    than ``low`` or more than ``high`` fields."""
    if not low <= len(tokens) <= high:
        raise FormatError(path, line, f"expected {what}, found {' '.join(tokens)!r}")


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


def orient_triangles(
    table: TriangleTable, points: Sequence[Point2], *, individually: bool, notes: list[str]
) -> list[tuple[int, int, int]]:
    """The triangles of ``table`` made counter-clockwise (exact ``orient2d``).

    A degenerate triangle (a repeated or collinear corner) is a FormatError naming it.
    With ``individually`` each clockwise triangle is reversed.  Otherwise the file must be
    consistent: all clockwise is reversed (and noted), a mix is a FormatError naming the
    first clockwise and the first counter-clockwise triangle.
    """
    clockwise = Orientation.CLOCKWISE
    collinear = Orientation.COLLINEAR
    path = table.path
    result: list[tuple[int, int, int]] = []
    first_cw: int | None = None
    first_ccw: int | None = None
    reversed_count = 0
    for index, (a, b, c) in enumerate(table.triangles):
        if a in (b, c) or b == c:
            raise FormatError(
                path, table.lines[index], f"{table.describe(index)} repeats a vertex"
            )
        orientation = orient2d(points[a], points[b], points[c])
        if orientation == collinear:
            raise FormatError(
                path,
                table.lines[index],
                f"{table.describe(index)} is degenerate: its corners are collinear",
            )
        if orientation == clockwise:
            if first_cw is None:
                first_cw = index
            result.append((a, c, b))
            reversed_count += 1
        else:
            if first_ccw is None:
                first_ccw = index
            result.append((a, b, c))
        if not individually and first_cw is not None and first_ccw is not None:
            later = max(first_cw, first_ccw)
            raise FormatError(
                path,
                table.lines[later],
                f"{table.noun}s have mixed orientations: {table.describe(first_cw)} is "
                f"clockwise but {table.describe(first_ccw)} is counter-clockwise",
            )
    total = len(result)
    if reversed_count:
        if reversed_count == total:
            notes.append(all_clockwise_note(total, table.noun))
        else:
            notes.append(
                f"{reversed_count} of {counted(total, table.noun)} were clockwise; reversed "
                f"{'it' if reversed_count == 1 else 'them'}"
            )
    return result


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
) -> Mesh2:
    """A :class:`Mesh2` from checked tables (indices already 0-based and in range).

    Checks, each a FormatError naming the file and line: duplicate vertices, degenerate
    triangles, orientation (see :func:`orient_triangles`), two triangles on the same side
    of an edge (overlap), segments with equal ends.  Notes vertices in no triangle.
    """
    used = {vertex for triangle in table.triangles for vertex in triangle}
    check_distinct_points(point_path, points, point_lines, used, notes, table.vertex_base)
    oriented = orient_triangles(
        table, points, individually=orient_individually, notes=notes
    )
    transient = Transient2(empty_mesh())
    for index, point in enumerate(points):
        marker = vertex_markers[index] if vertex_markers is not None else 0
        attributes = vertex_attributes[index] if vertex_attributes is not None else ()
        transient.add_vertex(point, marker, attributes)
    triangle_attributes = table.attributes
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
    unused = len(points) - len(used)
    if unused and oriented:
        notes.append(
            f"{unused} of {counted(len(points), 'vertex', 'vertices')} "
            f"{'is' if unused == 1 else 'are'} in no triangle"
        )
    return mesh


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
    numbers it rounds.  A transient: one per write call."""

    __slots__ = ("rounded", "style")

    def __init__(self, style: NumberStyle) -> None:
        if style not in NUMBER_STYLES:
            raise ValueError(f"unknown number style {style!r} (known: {NUMBER_STYLES})")
        self.style = style
        self.rounded = 0

    def __call__(self, value: Rational) -> str:
        if self.style == "float":
            if value.denominator == 1 and abs(value.numerator) <= _EXACT_INTEGER_LIMIT:
                return mpz_text(value.numerator)
        else:
            text = exact_decimal_text(value)
            if text is not None:
                return text
            if self.style == "exact":
                return f"{mpz_text(value.numerator)}/{mpz_text(value.denominator)}"
        text, exact = nearest_double_text(value)
        if not exact:
            self.rounded += 1
        return text


def mpz_text(value: Any) -> str:
    """Decimal digits of an integer of any size (gmpy2 has no int-to-str digit limit)."""
    return str(gmpy2.mpz(value).digits(10))


def exact_decimal_text(value: Rational) -> str | None:
    """The exact decimal text of ``value`` (``"0.125"``, ``"-3"``, ``"1.5e-30"`` when the
    exponent form is shorter), or None when its decimal expansion does not terminate.
    Linear in the size of the number: the denominator 2^a 5^b is made 10^max(a, b) in one
    multiplication."""
    numerator = gmpy2.mpz(value.numerator)
    denominator = gmpy2.mpz(value.denominator)
    if denominator == 1:
        digits = mpz_text(abs(numerator))
        stripped = digits.rstrip("0") or "0"
        return _decimal_text(numerator < 0, stripped, len(stripped) - len(digits))
    rest, twos = gmpy2.remove(denominator, 2)
    rest, fives = gmpy2.remove(rest, 5)
    if rest != 1:
        return None
    scale = max(twos, fives)
    digits_value = abs(numerator) * gmpy2.mpz(2) ** (scale - twos) * gmpy2.mpz(5) ** (
        scale - fives
    )
    return _decimal_text(numerator < 0, mpz_text(digits_value), scale)


def _decimal_text(negative: bool, digits: str, scale: int) -> str:
    """``± digits * 10^-scale`` (digits without leading zeros, the last one nonzero) as
    the shorter of the plain and the exponent form."""
    sign = "-" if negative else ""
    if scale <= 0:
        plain = digits + "0" * -scale
    elif len(digits) > scale:
        plain = f"{digits[:-scale]}.{digits[-scale:]}"
    else:
        plain = "0." + "0" * (scale - len(digits)) + digits
    significant = digits.rstrip("0") or "0"
    exponent = len(digits) - 1 - scale
    mantissa = significant[0] + ("." + significant[1:] if len(significant) > 1 else "")
    scientific = f"{mantissa}e{exponent}"
    # the plain form reads best; the exponent form only where it saves a run of zeros
    return sign + (scientific if len(scientific) + _ZEROS_WORTH_AN_EXPONENT < len(plain) else plain)


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
    digits = mpz_text(digits_value)
    stripped = digits.rstrip("0")
    return _decimal_text(value < 0, stripped, scale - (len(digits) - len(stripped))), (
        remainder == 0
    )


_PART_NOUNS = {
    "vertex markers": ("nonzero vertex marker", "nonzero vertex markers"),
    "vertex attributes": ("vertex with attributes", "vertices with attributes"),
    "triangle attributes": ("triangle with attributes (regions)",
                            "triangles with attributes (regions)"),
    "segments": ("segment", "segments"),
    "holes": ("hole", "holes"),
    "regions": ("region", "regions"),
}


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
    files: Sequence[tuple[Path, str]],
    *,
    overwrite: bool,
    numbers: NumberText | None = None,
    dropped: tuple[str, ...] = (),
) -> WriteReport:
    """Write each (path, text) atomically; when not ``overwrite``, refuse (OverwriteError)
    before writing anything if any target exists.  The report counts what ``numbers``
    rounded and lists what was ``dropped``."""
    if not overwrite:
        for path, _ in files:
            if path.exists():
                raise OverwriteError(str(path))
    written: list[Path] = []
    for path, text in files:
        write_text_atomic(path, text, overwrite=overwrite)
        written.append(path)
    return WriteReport(
        tuple(written), numbers.rounded if numbers is not None else 0, dropped
    )


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


def with_extension(stem: Path, extension: str) -> Path:
    """``stem`` + ``extension`` (appended, never replacing a dotted part of the stem)."""
    return stem.with_name(stem.name + extension)
