"""Public hypothesis strategies for geomexact values.

Every strategy returns exact objects (``mpq`` rationals, :class:`~geomexact.kernel.points.Point2` /
:class:`~geomexact.kernel.points.Point3` built with :func:`~geomexact.kernel.points.point2` /
:func:`~geomexact.kernel.points.point3`).  Size and range arguments are validated eagerly: a bad
argument raises ``hypothesis.errors.InvalidArgument`` when the strategy is built, as in
hypothesis itself.

Sections: scalars; points (with degenerate and near-degenerate configurations for the
predicates); meshes (at the end of the file).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any, Literal, Protocol, TypeAlias, TypeVar

from geomexact.errors import MissingDependencyError

try:
    from hypothesis import strategies as st
    from hypothesis.errors import InvalidArgument
except ImportError as error:  # the "strategies" extra
    raise MissingDependencyError("hypothesis", "geomexact.strategies", "strategies") from error

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import Rational, mpq
from geomexact.kernel.points import Point2, Point3, point2, point3
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates2d import orient2d
from geomexact.mesh2d import ops
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh2d.transient import Transient2, mesh_from_triangles
from geomexact.trace.record import Trace, trace_of

__all__ = [
    "MAGNITUDES",
    "Magnitude",
    "cocircular_quadruples",
    "collinear_triples",
    "coordinates",
    "coplanar_quadruples",
    "cospherical_quintuples",
    "decimal_rationals",
    "dyadic_rationals",
    "extreme_rationals",
    "near_degenerate_points2",
    "near_degenerate_points3",
    "points2",
    "points3",
    "rationals",
]

_Drawn = TypeVar("_Drawn")
_Drawn_co = TypeVar("_Drawn_co", covariant=True)

Magnitude: TypeAlias = Literal["ordinary", "decimal", "dyadic", "huge", "tiny", "beyond_double"]
MAGNITUDES: tuple[Magnitude, ...] = (
    "ordinary",
    "decimal",
    "dyadic",
    "huge",
    "tiny",
    "beyond_double",
)


def _check_int(name: str, value: object, low: int, high: int | None = None) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise InvalidArgument(f"{name}={value!r} must be an int")
    if value < low or (high is not None and value > high):
        upper = "" if high is None else f" and <= {high}"
        raise InvalidArgument(f"{name}={value!r} must be >= {low}{upper}")
    return value


def _check_magnitudes(magnitudes: Sequence[Magnitude]) -> tuple[Magnitude, ...]:
    if isinstance(magnitudes, str):
        raise InvalidArgument(
            f"magnitudes={magnitudes!r} must be a sequence of names, e.g. ('huge',)"
        )
    chosen = tuple(dict.fromkeys(magnitudes))
    if not chosen:
        raise InvalidArgument("magnitudes must name at least one magnitude")
    unknown = [name for name in chosen if name not in MAGNITUDES]
    if unknown:
        raise InvalidArgument(f"unknown magnitudes {unknown}; choose from {MAGNITUDES}")
    return chosen


# =======================================================================================
# Scalars
# =======================================================================================


def rationals(
    *, max_numerator: int = 10**6, max_denominator: int = 10**6
) -> st.SearchStrategy[Rational]:
    """Rationals p/q with |p| <= ``max_numerator`` and 1 <= q <= ``max_denominator``."""
    _check_int("max_numerator", max_numerator, 0)
    _check_int("max_denominator", max_denominator, 1)
    return st.builds(
        mpq,
        st.integers(-max_numerator, max_numerator),
        st.integers(1, max_denominator),
    )


def decimal_rationals(*, max_digits: int = 12, max_places: int = 8) -> st.SearchStrategy[Rational]:
    """Finite decimals such as 0.1, -2.75, 1234.5678 (``max_digits`` significant digits,
    at most ``max_places`` after the point); most are not exact doubles."""
    _check_int("max_digits", max_digits, 1, 400)
    _check_int("max_places", max_places, 0, 400)
    return st.builds(
        lambda digits, places: mpq(digits, 10**places),
        st.integers(-(10**max_digits - 1), 10**max_digits - 1),
        st.integers(0, max_places),
    )


def dyadic_rationals(*, max_exponent: int = 60) -> st.SearchStrategy[Rational]:
    """Exact binary values of finite doubles (``m * 2^e``, 53-bit m, |e| <= max_exponent):
    their floats carry no rounding error."""
    _check_int("max_exponent", max_exponent, 0, 1074)
    return st.builds(
        lambda mantissa, exponent: mpq(mantissa) * mpq(2) ** exponent,
        st.integers(-(2**53 - 1), 2**53 - 1),
        st.integers(-max_exponent, max_exponent),
    )


def extreme_rationals(
    *, min_exponent: int = -400, max_exponent: int = 400, max_digits: int = 6
) -> st.SearchStrategy[Rational]:
    """``m * 10^e`` with a small integer m and ``min_exponent <= e <= max_exponent``.

    The defaults reach beyond the double range on both sides: 1e400 has no double (its
    float is ``nan`` in a point), 1e-400 rounds to 0.0 and 1e-310 to a subnormal.
    """
    _check_int("min_exponent", min_exponent, -100_000, 100_000)
    _check_int("max_exponent", max_exponent, min_exponent, 100_000)
    _check_int("max_digits", max_digits, 1, 100)
    return st.builds(
        lambda mantissa, exponent: mpq(mantissa) * mpq(10) ** exponent,
        st.integers(-(10**max_digits - 1), 10**max_digits - 1),
        st.integers(min_exponent, max_exponent),
    )


def coordinates(magnitudes: Sequence[Magnitude] = MAGNITUDES) -> st.SearchStrategy[Rational]:
    """Coordinates drawn from the named ``magnitudes`` (any non-empty subset of
    :data:`MAGNITUDES`): ``ordinary`` p/q, ``decimal`` (0.1, ...), ``dyadic`` (exact
    doubles), ``huge`` (1e150..1e300), ``tiny`` (1e-300..1e-150, and down to subnormal
    1e-320), ``beyond_double`` (1e309..1e400 and 1e-400..1e-330)."""
    chosen = _check_magnitudes(magnitudes)
    table: dict[str, st.SearchStrategy[Rational]] = {
        "ordinary": rationals(),
        "decimal": decimal_rationals(),
        "dyadic": dyadic_rationals(),
        "huge": extreme_rationals(min_exponent=150, max_exponent=300),
        "tiny": extreme_rationals(min_exponent=-320, max_exponent=-150),
        "beyond_double": st.one_of(
            extreme_rationals(min_exponent=309, max_exponent=400),
            extreme_rationals(min_exponent=-400, max_exponent=-330),
        ),
    }
    return st.one_of(*(table[name] for name in chosen))


# =======================================================================================
# Points
# =======================================================================================


def points2(
    coordinate: st.SearchStrategy[Rational] | None = None,
) -> st.SearchStrategy[Point2]:
    """Exact plane points whose coordinates come from ``coordinate`` (default: every
    magnitude of :func:`coordinates`)."""
    values = coordinates() if coordinate is None else coordinate
    return st.builds(point2, values, values)


def points3(
    coordinate: st.SearchStrategy[Rational] | None = None,
) -> st.SearchStrategy[Point3]:
    """Exact space points whose coordinates come from ``coordinate``."""
    values = coordinates() if coordinate is None else coordinate
    return st.builds(point3, values, values, values)


# ---- degenerate configurations --------------------------------------------------------
# Each configuration is built in a small "unit" frame with exact rational parameters and
# then mapped by a similarity x -> scale * x + offset (which keeps collinearity,
# cocircularity, coplanarity, cosphericity) with scale and offset of any magnitude.

_UNIT = rationals(max_numerator=1000, max_denominator=97)
_PARAMETER = rationals(max_numerator=200, max_denominator=60)


def _scales(magnitudes: Sequence[Magnitude]) -> st.SearchStrategy[Rational]:
    return coordinates(magnitudes).filter(lambda value: value != 0)


class _MagnitudeStrategy(Protocol[_Drawn_co]):
    """A strategy of configurations placed by rationals of ``magnitudes``."""

    def __call__(self, magnitudes: Sequence[Magnitude] = ...) -> st.SearchStrategy[_Drawn_co]:
        ...


def _magnitudes_checked(
    strategy: Callable[[Sequence[Magnitude]], st.SearchStrategy[_Drawn]],
) -> _MagnitudeStrategy[_Drawn]:
    """``strategy`` taking ``magnitudes`` (default: all of them), checked when it is
    called (``InvalidArgument`` at once, as hypothesis's own strategies do)."""

    def checked(magnitudes: Sequence[Magnitude] = MAGNITUDES) -> st.SearchStrategy[_Drawn]:
        return strategy(_check_magnitudes(magnitudes))

    # its name and contract; help shows its own signature, with the default
    checked.__name__ = checked.__qualname__ = strategy.__name__
    checked.__doc__, checked.__module__ = strategy.__doc__, strategy.__module__
    return checked


def _similarity(
    draw: st.DrawFn, magnitudes: Sequence[Magnitude], dimension: int
) -> Callable[[Sequence[Rational]], list[Rational]]:
    """Draw a scale (not 0), then an offset, of ``magnitudes``: the similarity
    x -> scale * x + offset that places a configuration built in the unit frame."""
    scale = draw(_scales(magnitudes))
    offset = [draw(coordinates(magnitudes)) for _ in range(dimension)]
    return lambda unit: [o + scale * x for o, x in zip(offset, unit, strict=True)]


@_magnitudes_checked
@st.composite
def collinear_triples(
    draw: st.DrawFn, magnitudes: Sequence[Magnitude]
) -> tuple[Point2, Point2, Point2]:
    """Three exactly collinear points (in random order, possibly repeated), scaled and
    translated by rationals of ``magnitudes``."""
    place = _similarity(draw, magnitudes, 2)
    ax, ay, bx, by = (draw(_UNIT) for _ in range(4))
    t = draw(_PARAMETER)
    raw = [(ax, ay), (bx, by), (ax + t * (bx - ax), ay + t * (by - ay))]
    order = draw(st.permutations(range(3)))
    a, b, c = (point2(*place(raw[i])) for i in order)
    return a, b, c


def _circle_point(s: Rational) -> tuple[Rational, Rational]:
    """The rational point of the unit circle with parameter s (stereographic)."""
    w = 1 + s * s
    return (1 - s * s) / w, 2 * s / w


@_magnitudes_checked
@st.composite
def cocircular_quadruples(
    draw: st.DrawFn, magnitudes: Sequence[Magnitude]
) -> tuple[Point2, Point2, Point2, Point2]:
    """Four distinct points on one circle with rational center and radius, scaled and
    translated by rationals of ``magnitudes``."""
    place = _similarity(draw, magnitudes, 2)
    radius = draw(_UNIT.filter(lambda r: r != 0))
    cx, cy = draw(_UNIT), draw(_UNIT)
    parameters = draw(st.lists(_PARAMETER, min_size=4, max_size=4, unique=True))
    points = []
    for s in parameters:
        ux, uy = _circle_point(s)
        points.append(point2(*place((cx + radius * ux, cy + radius * uy))))
    a, b, c, d = points
    return a, b, c, d


@_magnitudes_checked
@st.composite
def coplanar_quadruples(
    draw: st.DrawFn, magnitudes: Sequence[Magnitude]
) -> tuple[Point3, Point3, Point3, Point3]:
    """Four exactly coplanar space points, scaled and translated by ``magnitudes``."""
    place = _similarity(draw, magnitudes, 3)
    base = [draw(_UNIT) for _ in range(3)]
    u = [draw(_UNIT) for _ in range(3)]
    v = [draw(_UNIT) for _ in range(3)]
    points = []
    for _ in range(4):
        s, r = draw(_PARAMETER), draw(_PARAMETER)
        points.append(point3(*place([base[i] + s * u[i] + r * v[i] for i in range(3)])))
    a, b, c, d = points
    return a, b, c, d


def _sphere_point(s: Rational, r: Rational) -> tuple[Rational, Rational, Rational]:
    """The rational point of the unit sphere with parameters (s, r) (stereographic)."""
    w = 1 + s * s + r * r
    return 2 * s / w, 2 * r / w, (s * s + r * r - 1) / w


@_magnitudes_checked
@st.composite
def cospherical_quintuples(
    draw: st.DrawFn, magnitudes: Sequence[Magnitude]
) -> tuple[Point3, Point3, Point3, Point3, Point3]:
    """Five distinct points on one sphere with rational center and radius, scaled and
    translated by rationals of ``magnitudes``."""
    place = _similarity(draw, magnitudes, 3)
    radius = draw(_UNIT.filter(lambda r: r != 0))
    center = [draw(_UNIT) for _ in range(3)]
    parameters = draw(
        st.lists(st.tuples(_PARAMETER, _PARAMETER), min_size=5, max_size=5, unique=True)
    )
    points = []
    for s, r in parameters:
        unit = _sphere_point(s, r)
        points.append(point3(*place([center[i] + radius * unit[i] for i in range(3)])))
    a, b, c, d, e = points
    return a, b, c, d, e


# ---- near-degenerate configurations ----------------------------------------------------


@st.composite
def _nudged(draw: st.DrawFn, value: Rational) -> Rational:
    """``value`` moved by a tiny amount: +-2^-k times its magnitude (k up to 110), or one
    ulp of its double (to the neighbouring double, or by the ulp as a rational step)."""
    magnitude = abs(value) if value != 0 else mpq(1)
    kind = draw(st.sampled_from(("power", "ulp_step", "next_double", "none")))
    sign = draw(st.sampled_from((-1, 1)))
    if kind == "power":
        return value + sign * magnitude * mpq(1, 2 ** draw(st.integers(20, 110)))
    try:
        approx = float(value)
    except OverflowError:
        return value + sign * magnitude * mpq(1, 2**60)
    if kind == "ulp_step":
        return value + sign * mpq(math.ulp(approx))
    if kind == "next_double":
        return mpq(math.nextafter(approx, sign * math.inf))
    return value


def near_degenerate_points2(
    count: int = 3, magnitudes: Sequence[Magnitude] = MAGNITUDES
) -> st.SearchStrategy[tuple[Point2, ...]]:
    """``count`` plane points that are nearly (or exactly) degenerate: a collinear triple
    (``count=3``) or a cocircular quadruple (``count=4``) with one point's coordinates
    nudged by +-2^-k relative, by one ulp, or to the next double."""
    _check_int("count", count, 3, 4)
    chosen = _check_magnitudes(magnitudes)
    base = collinear_triples(chosen) if count == 3 else cocircular_quadruples(chosen)
    return _nudge_one(base, point2)


def near_degenerate_points3(
    count: int = 4, magnitudes: Sequence[Magnitude] = MAGNITUDES
) -> st.SearchStrategy[tuple[Point3, ...]]:
    """``count`` space points that are nearly (or exactly) degenerate: a coplanar
    quadruple (``count=4``) or a cospherical quintuple (``count=5``) with one point
    nudged as in :func:`near_degenerate_points2`."""
    _check_int("count", count, 4, 5)
    chosen = _check_magnitudes(magnitudes)
    base = coplanar_quadruples(chosen) if count == 4 else cospherical_quintuples(chosen)
    return _nudge_one(base, point3)


@st.composite
def _nudge_one(
    draw: st.DrawFn, base: st.SearchStrategy[tuple[Any, ...]], make: Callable[..., Any]
) -> tuple[Any, ...]:
    points = draw(base)
    index = draw(st.integers(0, len(points) - 1))
    target = points[index]
    dimension = len(target) // 2
    moved = make(*(draw(_nudged(target[i])) for i in range(dimension)))
    return (*points[:index], moved, *points[index + 1 :])


# =======================================================================================
# Meshes
# =======================================================================================


@st.composite
def convex_polygons(
    draw: st.DrawFn, min_size: int = 3, max_size: int = 8, coordinate_bits: int = 8
) -> list[Point2]:
    """Vertices of a strictly convex polygon, counter-clockwise: the convex hull of random
    lattice points scaled by a random denominator (a unit triangle when they are collinear).
    """
    _check_int("min_size", min_size, 3)
    _check_int("max_size", max_size, min_size)
    _check_int("coordinate_bits", coordinate_bits, 1, 60)
    size = draw(st.integers(min_size, max_size))
    limit = 1 << coordinate_bits
    denominator = draw(st.sampled_from([1, 3, 10, 1 << coordinate_bits]))
    raw = draw(st.lists(st.tuples(st.integers(0, limit), st.integers(0, limit)),
                        min_size=size, max_size=size, unique=True))
    points = [point2(mpq(x, denominator), mpq(y, denominator)) for x, y in raw]
    hull = _convex_hull(points)
    if len(hull) < 3:
        hull = [point2(0, 0), point2(1, 0), point2(0, 1)]
    return hull


_LEFT = Orientation.COUNTERCLOCKWISE


def _convex_hull(points: list[Point2]) -> list[Point2]:
    unique = sorted(set(points), key=lambda p: (p.x, p.y))
    if len(unique) < 3:
        return unique

    def half(sequence: list[Point2]) -> list[Point2]:
        chain: list[Point2] = []
        for p in sequence:
            while len(chain) >= 2 and orient2d(chain[-2], chain[-1], p) != _LEFT:
                chain.pop()
            chain.append(p)
        return chain

    lower, upper = half(unique), half(unique[::-1])
    return lower[:-1] + upper[:-1]


STEP_KINDS = ("flip", "bisect", "insert_in_triangle", "insert_in_edge", "insert_centroid",
              "insert_vertex_centroid")


@st.composite
def meshes_with_traces(
    draw: st.DrawFn,
    max_steps: int = 20,
    constrained_boundary: bool | None = None,
    kinds: Sequence[str] = STEP_KINDS,
) -> tuple[Mesh2, Mesh2, Trace]:
    """(start, end, trace): a fan-triangulated strictly convex polygon (boundary
    constrained or not), then up to ``max_steps`` random valid steps of ``kinds``; the trace
    replays ``start`` to ``end``."""
    if max_steps < 0:
        raise ValueError("max_steps must be >= 0")
    polygon = draw(convex_polygons())
    constrained = draw(st.booleans()) if constrained_boundary is None else constrained_boundary
    n = len(polygon)
    segments = [(i, (i + 1) % n, 1) for i in range(n)] if constrained else []
    start = mesh_from_triangles(polygon, [(0, i, i + 1) for i in range(1, n - 1)], segments)
    transient = Transient2(start)
    count = draw(st.integers(0, max_steps))
    for _ in range(count):
        _random_step(draw, transient, kinds)
    end = transient.seal()
    return start, end, trace_of(start, transient, {"strategy": "meshes_with_traces"})


def _random_step(draw: st.DrawFn, t: Transient2, kinds: Sequence[str]) -> None:
    kind = draw(st.sampled_from(list(kinds)))
    snapshot_edges = sorted(t.iter_edges())
    if not snapshot_edges:
        return
    u, v = draw(st.sampled_from(snapshot_edges))
    try:
        if kind == "flip":
            ops.flip_in(t, u, v)
        elif kind == "bisect":
            ops.bisect_in(t, u, v)
        elif kind == "insert_in_edge":
            pu, pv = t.point(u), t.point(v)
            k = draw(st.integers(1, 6))
            point = point2(pu.x + (pv.x - pu.x) * k / 7, pu.y + (pv.y - pu.y) * k / 7)
            ops.insert_in_edge_in(t, u, v, point)
        elif kind == "insert_in_triangle":
            w = t.apex(u, v)
            if w is None:
                u, v = v, u
                w = t.apex(u, v)
            assert w is not None
            weights = draw(st.tuples(*(st.integers(1, 9),) * 3))
            a, b, c = t.point(u), t.point(v), t.point(w)
            total = sum(weights)
            point = point2(
                (weights[0] * a.x + weights[1] * b.x + weights[2] * c.x) / total,
                (weights[0] * a.y + weights[1] * b.y + weights[2] * c.y) / total,
            )
            ops.insert_in_triangle_in(t, (u, v, w), point)
        elif kind == "insert_centroid":
            ops.insert_centroid_in(t, u, v, kind="area")
        else:
            ops.insert_centroid_in(t, u, v, kind="vertices")
    except PreconditionError:
        pass  # the drawn edge did not suit this op (boundary, non-convex…): skip it


def triangulations(max_steps: int = 20) -> st.SearchStrategy[Mesh2]:
    """Valid triangle meshes: the ``end`` of :func:`meshes_with_traces`."""
    return meshes_with_traces(max_steps=max_steps).map(lambda case: case[1])


@st.composite
def simple_polygons(
    draw: st.DrawFn, min_size: int = 3, max_size: int = 12, *, scale: int = 16
) -> list[Point2]:
    """Vertices of a simple polygon, counter-clockwise: points at strictly increasing
    angles around the origin (rational points of the unit circle) and random rational
    radii in [scale/4, scale], so the polygon is star-shaped and may be very non-convex."""
    _check_int("min_size", min_size, 3)
    _check_int("max_size", max_size, min_size)
    _check_int("scale", scale, 1)
    size = draw(st.integers(min_size, max_size))
    # directions at parameters -2, 0, 2 (angles about -127°, 0°, 127°) are always present, so
    # consecutive vertices turn by less than 180° around the origin: the polygon is simple
    anchors = {-16, 0, 16}
    extra = draw(st.lists(st.integers(-64, 64).filter(lambda k: k not in anchors),
                          min_size=size - 3, max_size=size - 3, unique=True))
    parameters = sorted(anchors | set(extra))
    polygon = []
    for parameter in parameters:
        ux, uy = _circle_point(mpq(parameter, 8))
        radius = mpq(draw(st.integers(scale, 4 * scale)), 4)
        polygon.append(point2(radius * ux, radius * uy))
    area = sum(
        (p.x * q.y - q.x * p.y for p, q in zip(polygon, polygon[1:] + polygon[:1], strict=True)),
        mpq(0),
    )
    return polygon if area > 0 else polygon[::-1]


@st.composite
def pslgs(
    draw: st.DrawFn, max_boundary: int = 10, max_points: int = 10, holes: bool = True
) -> PSLG:
    """A PSLG: a simple polygon (segments with marker 1), possibly a hole polygon near its
    centre (segments with marker 2, its seed point in ``holes``) and free points strictly
    inside the domain.  Exact coordinates."""
    _check_int("max_boundary", max_boundary, 3)
    _check_int("max_points", max_points, 0)
    outer = draw(simple_polygons(3, max_boundary, scale=16))
    vertices = list(outer)
    n = len(outer)
    segments = [(i, (i + 1) % n, 1) for i in range(n)]
    hole_seeds: list[Point2] = []
    # the disk of radius 2 around the origin is inside the outer polygon when every outer
    # edge's line is farther than 2 from the origin (outer radii are at least 4)
    clear = all(_line_distance_squared_exceeds(p, q, 4) for p, q in
                zip(outer, outer[1:] + outer[:1], strict=True))
    if holes and clear and draw(st.booleans()):
        hole = [point2(x, y) for x, y in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
        start = len(vertices)
        vertices.extend(hole)
        segments.extend((start + i, start + (i + 1) % 4, 2) for i in range(4))
        hole_seeds.append(point2(0, 0))
    count = draw(st.integers(0, max_points))
    for _ in range(count):
        candidate = point2(mpq(draw(st.integers(-64, 64)), 8), mpq(draw(st.integers(-64, 64)), 8))
        if candidate in vertices or not _inside_simple(candidate, outer):
            continue
        if hole_seeds and abs(candidate.x) <= 1 and abs(candidate.y) <= 1:
            continue
        vertices.append(candidate)
    return PSLG(vertices=vertices, segments=segments, holes=hole_seeds)


def _line_distance_squared_exceeds(p: Point2, q: Point2, limit: int) -> bool:
    cross = p.x * q.y - q.x * p.y
    length2 = (q.x - p.x) ** 2 + (q.y - p.y) ** 2
    return bool(cross * cross > limit * length2)


def _inside_simple(point: Point2, polygon: Sequence[Point2]) -> bool:
    """Strictly inside (crossing number, exact; points on the border count as outside)."""
    inside = False
    for p, q in zip(polygon, [*polygon[1:], polygon[0]], strict=True):
        if orient2d(p, q, point) == Orientation.COLLINEAR and (
            min(p.x, q.x) <= point.x <= max(p.x, q.x) and min(p.y, q.y) <= point.y <= max(p.y, q.y)
        ):
            return False
        if (p.y > point.y) != (q.y > point.y):
            x = p.x + (point.y - p.y) * (q.x - p.x) / (q.y - p.y)
            if x > point.x:
                inside = not inside
    return inside
