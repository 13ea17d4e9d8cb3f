"""The partition of a 1-irregular cuboid into tetrahedra by bisection, and its Joe-flip
improvement: the reference implementation (exact, on :class:`Mesh3`).

:func:`partition_cuboid` starts from the template's five tetrahedra on the box's corners
(vertex ids 0..7 are the corners), splits, in the chosen order, the segment of each
Steiner point (``split_tetra``: the cube edge, or the face's diagonal for a face centre;
the Steiner points get ids 8, 9, … in that order), then optionally improves the mesh.  It
returns the start, the partition, the final mesh and the trace that replays the whole run
from the start.  Specification: ``specs/cuboid.md``.
"""

from __future__ import annotations

from typing import Any, Final

import attrs

from geomexact._version import __version__
from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import format_rational
from geomexact.mesh3d.cuboid.boxes import Box, unit_cube
from geomexact.mesh3d.cuboid.improvement import ImprovementReport, improve_in
from geomexact.mesh3d.cuboid.numbering import (
    BIT_COUNT,
    CORNER_POSITIONS,
    check_pattern,
    steiner_position2,
)
from geomexact.mesh3d.cuboid.split_order import SplitOrder, check_order, split_sequence
from geomexact.mesh3d.cuboid.templates import TEMPLATE_TETRAHEDRA, check_template, segment_of
from geomexact.mesh3d.ops import split_tetra_in
from geomexact.mesh3d.snapshot import Mesh3
from geomexact.mesh3d.transient import mesh3_from_tetrahedra
from geomexact.trace.record import Trace

__all__ = ["CuboidMesh", "initial_mesh", "partition_cuboid", "point_label", "recorded_start"]

POINT_CODES: Final = 8 + BIT_COUNT
"""Point codes: corner k is k (0..7), the Steiner point of bit i is 8 + i."""


def point_label(code: int) -> str:
    """``"c3"`` for corner 3, ``"e5"`` for the midpoint of edge 5, ``"f12"`` for the centre
    of face 12."""
    if code < 8:
        return f"c{code}"
    bit = code - 8
    return f"e{bit}" if bit < 12 else f"f{bit}"


@attrs.frozen(slots=True)
class CuboidMesh:
    """A partitioned (and maybe improved) cuboid: the run's inputs, ``start`` (the
    template's five tetrahedra), ``partition`` (after every split), ``mesh`` (after the
    improvement; the partition itself without one), ``trace`` (from ``start``: the splits,
    then the flips), ``steiner`` (the (bit, vertex id) of each Steiner point in insertion
    order) and the improvement's report (None without one)."""

    pattern: int
    box: Box
    order: SplitOrder
    template: int
    start: Mesh3
    partition: Mesh3
    mesh: Mesh3
    trace: Trace
    steiner: tuple[tuple[int, int], ...]
    improvement: ImprovementReport | None

    @property
    def split_count(self) -> int:
        return len(self.steiner)

    def point_codes(self) -> dict[int, int]:
        """Vertex id -> its point code (corner k -> k, Steiner point of bit i -> 8 + i)."""
        codes = {k: k for k in range(8)}
        codes.update((vertex, 8 + bit) for bit, vertex in self.steiner)
        return codes

    def face_triangulations(self, mesh: Mesh3 | None = None) -> dict[int, tuple[tuple[int, ...],
                                                                                   ...]]:
        """Face bit (12..17) -> the triangles of ``mesh`` (default: the final mesh) on that
        box face, as point-code triples oriented outward, each rotated to start at its
        smallest code, sorted: they depend only on the face's own Steiner points, the
        template and the order (``specs/cuboid.md``)."""
        codes = self.point_codes()
        found: dict[int, list[tuple[int, ...]]] = {12 + j: [] for j in range(6)}
        for face in (mesh or self.mesh).boundary_faces():
            triple = tuple(codes[v] for v in face)
            found[_box_face_of(triple)].append(_rotated(triple))
        return {bit: tuple(sorted(triangles)) for bit, triangles in found.items()}


def _position2(code: int) -> tuple[int, int, int]:
    if code < 8:
        x, y, z = CORNER_POSITIONS[code]
        return (2 * x, 2 * y, 2 * z)
    return steiner_position2(code - 8)


def _box_face_of(codes: tuple[int, ...]) -> int:
    positions = [_position2(code) for code in codes]
    for axis in range(3):
        values = {p[axis] for p in positions}
        if len(values) == 1 and values != {1}:
            return 12 + 2 * axis + (values.pop() // 2)
    raise AssertionError(f"boundary triangle {codes} is on no box face")  # pragma: no cover


def _rotated(triple: tuple[int, ...]) -> tuple[int, ...]:
    i = triple.index(min(triple))
    return triple[i:] + triple[:i]


def initial_mesh(box: Box, template: int = 0) -> Mesh3:
    """The template's five tetrahedra on the box's corners (vertex k = corner k)."""
    check_template(template)
    return mesh3_from_tetrahedra([box.corner(k) for k in range(8)],
                                 TEMPLATE_TETRAHEDRA[template])


def recorded_start(trace: Trace) -> Mesh3:
    """The start mesh of a cuboid trace, rebuilt from the trace's own parameters (its
    ``box`` and ``template``): :func:`initial_mesh` of them.  A
    :class:`~geomexact.errors.PreconditionError` when ``trace`` was not written by
    :func:`partition_cuboid` or its parameters are malformed.  The caller still checks the
    digest (``trace.playback.replay`` does)."""
    start_box = recorded_box(trace)
    if trace.parameter("final") in ("mixed", "polyhedral"):
        raise PreconditionError(
            "recorded_start", "a trace of a cuboid's cell final starts from the cuboid's "
            "points (cell_templates.recorded_cell_start rebuilds it)")
    template = trace.parameter("template")
    if isinstance(template, bool) or template not in (0, 1):
        raise PreconditionError("recorded_start",
                                f"the trace's template {template!r} is not 0 or 1")
    return initial_mesh(start_box, template)


def recorded_box(trace: Trace) -> Box:
    """The box of a cuboid trace (its ``box`` parameter); a
    :class:`~geomexact.errors.PreconditionError` for another trace or a malformed box."""
    algorithm = trace.parameter("algorithm")
    if algorithm != "cuboid":
        shown = "none" if algorithm is None else repr(algorithm)
        raise PreconditionError(
            "recorded_start", f"not a cuboid trace (its algorithm is {shown}): only a "
            "cuboid trace records how to rebuild its start mesh")
    box = trace.parameter("box")
    try:
        low, high = box["low"], box["high"]
        if len(low) != 3 or len(high) != 3:
            raise ValueError("three coordinates each")
        return Box(tuple(low), tuple(high))
    except (TypeError, KeyError, ValueError) as error:  # RationalParseError is one
        raise PreconditionError(
            "recorded_start", "the trace's box is not {'low': [x, y, z], 'high': [x, y, z]} "
            f"of exact numbers with high > low ({error})") from error


def _parameters(pattern: int, box: Box, order: str, template: int, improve: bool,
                allow_boundary_flips: bool) -> dict[str, Any]:
    return {
        "algorithm": "cuboid",
        "pattern": pattern,
        "box": {"low": [format_rational(v) for v in box.low],
                "high": [format_rational(v) for v in box.high]},
        "order": order,
        "template": template,
        "improve": improve,
        "allow_boundary_flips": allow_boundary_flips,
    }


def partition_cuboid(
    pattern: int,
    box: Box | None = None,
    *,
    order: str = "conforming",
    template: int = 0,
    improve: bool = False,
    allow_boundary_flips: bool = False,
) -> CuboidMesh:
    """The partition of ``box`` (default: the unit cube) with the Steiner points of
    ``pattern`` (an int 0 .. 2**18 - 1), inserted in ``order`` ("conforming" or "index")
    from ``template`` (0 or 1), then improved by Joe's flips when ``improve``
    (:func:`~geomexact.mesh3d.cuboid.improvement.improve_in`).  Valid, with the box's
    exact volume; ``replay(result.start, result.trace) == result.mesh``."""
    check_pattern(pattern)
    split_order = check_order(order)
    check_template(template)
    box = box or unit_cube()
    start = initial_mesh(box, template)
    splitting = start.transient()
    steiner = []
    for bit in split_sequence(pattern, box, split_order):
        steiner.append((bit, split_tetra_in(splitting, *segment_of(bit, template))))
    steps, digests = list(splitting.steps), list(splitting.step_digests)
    partition = splitting.seal()
    mesh, report = partition, None
    if improve:
        improving = partition.transient()
        report = improve_in(improving, allow_boundary_flips=allow_boundary_flips)
        steps += improving.steps
        digests += improving.step_digests
        mesh = improving.seal()
    trace = Trace(start.digest, steps, digests,
                  _parameters(pattern, box, split_order, template, improve,
                              allow_boundary_flips), __version__)
    return CuboidMesh(pattern, box, split_order, template, start, partition, mesh, trace,
                      tuple(steiner), report)

