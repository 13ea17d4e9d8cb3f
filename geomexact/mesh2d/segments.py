"""Exact relations between straight segments given by vertex ids: do two segments meet
anywhere but at a shared endpoint, where do they cross, and which pairs of a set meet."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from geomexact.kernel.points import Point2, point2
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates2d import orient2d

Segment = tuple[int, int]


def within_box(p: Point2, q: Point2, r: Point2) -> bool:
    """True when p lies in the closed bounding box of q and r (for p on line qr: on the
    closed segment qr)."""
    return bool(min(q.x, r.x) <= p.x <= max(q.x, r.x) and min(q.y, r.y) <= p.y <= max(q.y, r.y))


def segments_meet_improperly(
    points: Mapping[int, Point2] | Sequence[Point2], first: Segment, second: Segment
) -> bool:
    """True when closed segments ``first`` and ``second`` share a point other than a common
    endpoint: a proper crossing, an endpoint of one on the other, a collinear overlap, or
    the same segment twice.  Exact."""
    (u, v), (a, b) = first, second
    pu, pv, pa, pb = points[u], points[v], points[a], points[b]
    shared = {u, v} & {a, b}
    if len(shared) == 2:
        return True
    o1, o2 = orient2d(pu, pv, pa), orient2d(pu, pv, pb)
    o3, o4 = orient2d(pa, pb, pu), orient2d(pa, pb, pv)
    if shared:
        if o1 == o2 == Orientation.COLLINEAR:  # overlapping beyond the common endpoint?
            common = shared.pop()
            end1 = points[v if common == u else u]
            end2 = points[b if common == a else a]
            pc = points[common]
            return bool((end1.x - pc.x) * (end2.x - pc.x) + (end1.y - pc.y) * (end2.y - pc.y) > 0)
        return False
    if o1 * o2 < 0 and o3 * o4 < 0:
        return True
    return any(
        orientation == Orientation.COLLINEAR and within_box(p, q, r)
        for orientation, p, q, r in (
            (o1, pa, pu, pv), (o2, pb, pu, pv), (o3, pu, pa, pb), (o4, pv, pa, pb)
        )
    )


def meeting_pairs(
    points: Mapping[int, Point2] | Sequence[Point2], segments: Sequence[Segment]
) -> list[tuple[Segment, Segment]]:
    """Every pair of ``segments`` that meet improperly (see
    :func:`segments_meet_improperly`), found by a sweep over x (exact): O(n log n + k·a)
    for a active segments per step.  Pairs are ordered by the sweep (deterministic)."""
    ordered = sorted(
        (min(points[u].x, points[v].x), max(points[u].x, points[v].x), u, v) for u, v in segments
    )
    found: list[tuple[Segment, Segment]] = []
    active: list[tuple[object, int, int]] = []
    for low, high, u, v in ordered:
        active = [entry for entry in active if entry[0] >= low]  # type: ignore[operator]
        for _, a, b in active:
            if segments_meet_improperly(points, (a, b), (u, v)):
                found.append(((a, b), (u, v)))
        active.append((high, u, v))
    return found


def crossing_point(p: Point2, q: Point2, r: Point2, s: Point2) -> Point2:
    """The exact intersection point of lines pq and rs (which must not be parallel)."""
    ux, uy = q.x - p.x, q.y - p.y
    vx, vy = s.x - r.x, s.y - r.y
    denominator = ux * vy - uy * vx
    if denominator == 0:
        raise ValueError("parallel lines have no single crossing point")
    t = ((r.x - p.x) * vy - (r.y - p.y) * vx) / denominator
    return point2(p.x + t * ux, p.y + t * uy)
