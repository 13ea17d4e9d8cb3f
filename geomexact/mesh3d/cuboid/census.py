"""The census of the 1-irregular cuboid: one :class:`CensusRow` per pattern (Joe's
configurations of the partition's interior faces, which of them fail the sphere test, and
what the improvement does), and the :class:`CensusSummary` of many rows.

:func:`census_row` computes a row with the reference implementation (exact, on
:class:`~geomexact.mesh3d.snapshot.Mesh3`); the compiled kernel
(:mod:`geomexact.mesh3d.cuboid.compiled`) computes the same rows much faster, and
``tests/mesh3d/test_cuboid_kernel.py`` proves them equal.  Columns: ``specs/cuboid.md``.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable
from functools import lru_cache
from typing import Any, Final

import attrs

from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.cuboid.improvement import (
    FLIP_NAMES,
    ImprovementReport,
    interior_faces_in,
    is_failing_in,
)
from geomexact.mesh3d.cuboid.partition import partition_cuboid
from geomexact.mesh3d.ops import FaceKind, classify_face_in
from geomexact.mesh3d.snapshot import Mesh3
from geomexact.mesh3d.validation import validate3

__all__ = [
    "CENSUS_COLUMNS",
    "KIND_ORDER",
    "TRANSFORMABLE_NAMES",
    "CensusRow",
    "CensusSummary",
    "census_row",
    "configuration_counts",
    "configuration_masks",
    "kind_mask",
    "kinds_of_mask",
    "summarize",
]

KIND_ORDER: Final[tuple[FaceKind, ...]] = tuple(FaceKind)
"""The configuration kinds in mask-bit order: T23, T32, T22, T44, N32, N44, N40, N30, N20."""
TRANSFORMABLE_NAMES: Final = ("T22", "T23", "T32", "T44")
_BIT: Final = {kind.value: 1 << i for i, kind in enumerate(KIND_ORDER)}


def kind_mask(kinds: Iterable[FaceKind | str]) -> int:
    """The bit mask of ``kinds`` (bit i: ``KIND_ORDER[i]``)."""
    mask = 0
    for kind in kinds:
        mask |= _BIT[FaceKind(kind).value]
    return mask


@lru_cache(maxsize=1 << len(KIND_ORDER))
def kinds_of_mask(mask: int) -> tuple[str, ...]:
    """The kind names of ``mask``, sorted by name."""
    return tuple(sorted(kind.value for i, kind in enumerate(KIND_ORDER) if mask >> i & 1))


def configuration_counts(mesh: Mesh3) -> dict[str, tuple[int, int]]:
    """Kind name -> (interior faces of that configuration, those failing the sphere
    test), for every kind in :data:`KIND_ORDER` order (zeros included)."""
    t = mesh.transient()
    counts = {kind.value: [0, 0] for kind in KIND_ORDER}
    for face in interior_faces_in(t):
        count = counts[classify_face_in(t, face).kind.value]
        count[0] += 1
        if is_failing_in(t, face):
            count[1] += 1
    return {name: (total, failing) for name, (total, failing) in counts.items()}


def configuration_masks(mesh: Mesh3) -> tuple[int, int]:
    """(the kinds of the interior faces, the kinds of those that fail the sphere test) of
    ``mesh``, as masks."""
    counts = configuration_counts(mesh)
    present = kind_mask(name for name, (total, _) in counts.items() if total)
    failing = kind_mask(name for name, (_, bad) in counts.items() if bad)
    return present, failing


def _kinds_text(mask: int | None) -> str | None:
    return None if mask is None else " ".join(kinds_of_mask(mask))


_CSV_NAMES: Final = tuple((name, f"{name}_failing", _BIT[name]) for name in TRANSFORMABLE_NAMES)


@attrs.frozen(slots=True)
class CensusRow:
    """The census of one pattern on one box, order and template.

    ``tetrahedra``, ``valid`` (validate3 with the box's volume), ``kinds`` and ``failing``
    (masks over :data:`KIND_ORDER`: the configurations of the partition's interior faces
    and those failing the sphere test) describe the partition; the rest the improvement
    (None without one): the flips of each kind (``flip23``, ``flip32``, ``flip22``,
    ``flip44``), ``rounds``, the improved mesh's ``tetrahedra_improved``,
    ``valid_improved`` and ``failing_improved`` (mask)."""

    pattern: int
    shape: str
    order: str
    template: int
    tetrahedra: int
    valid: bool
    kinds: int
    failing: int
    flips: tuple[int, int, int, int] | None = None
    rounds: int | None = None
    tetrahedra_improved: int | None = None
    valid_improved: bool | None = None
    failing_improved: int | None = None

    @property
    def delaunay(self) -> bool:
        """The partition as made has no locally non-Delaunay interior face."""
        return self.failing == 0

    @property
    def improved(self) -> bool:
        return self.flips is not None

    @property
    def delaunay_improved(self) -> bool | None:
        return None if self.failing_improved is None else self.failing_improved == 0

    def has(self, kind: str) -> bool:
        """The partition has an interior face of configuration ``kind``."""
        return bool(self.kinds & _BIT[kind])

    def fails(self, kind: str) -> bool:
        """The partition has a face of configuration ``kind`` failing its sphere test."""
        return bool(self.failing & _BIT[kind])

    def record(self) -> dict[str, Any]:
        """The row as a flat mapping over :data:`CENSUS_COLUMNS` (bools as 0/1, kind sets
        as space-separated names, None where the improvement did not run)."""
        flips = self.flips
        row: dict[str, Any] = {
            "pattern": self.pattern, "shape": self.shape, "order": self.order,
            "template": self.template, "tetrahedra": self.tetrahedra,
            "valid": int(self.valid), "delaunay": int(self.delaunay),
        }
        for name, failing_name, bit in _CSV_NAMES:
            row[name] = int(bool(self.kinds & bit))
            row[failing_name] = int(bool(self.failing & bit))
        row["failing_kinds"] = _kinds_text(self.failing)
        row["improved"] = int(self.improved)
        row["flips"] = None if flips is None else sum(flips)
        for index, name in enumerate(FLIP_NAMES):
            row[name] = None if flips is None else flips[index]
        row["rounds"] = self.rounds
        row["tetrahedra_improved"] = self.tetrahedra_improved
        row["valid_improved"] = None if self.valid_improved is None else int(self.valid_improved)
        delaunay = self.delaunay_improved
        row["delaunay_improved"] = None if delaunay is None else int(delaunay)
        row["failing_kinds_improved"] = _kinds_text(self.failing_improved)
        return row


CENSUS_COLUMNS: Final = tuple(CensusRow(0, "", "", 0, 0, True, 0, 0).record())
"""The columns of a census file, in order."""


def census_row(
    pattern: int,
    box: Box,
    *,
    order: str = "conforming",
    template: int = 0,
    improve: bool = False,
    allow_boundary_flips: bool = False,
) -> CensusRow:
    """The census row of ``pattern``, by the reference implementation."""
    run = partition_cuboid(pattern, box, order=order, template=template, improve=improve,
                           allow_boundary_flips=allow_boundary_flips)
    kinds, failing = configuration_masks(run.partition)
    row = CensusRow(pattern, box.describe(), run.order, template,
                    run.partition.tetrahedron_count,
                    not validate3(run.partition, volume=box.volume), kinds, failing)
    report: ImprovementReport | None = run.improvement
    if report is None:
        return row
    return attrs.evolve(
        row,
        flips=report.flips,
        rounds=report.rounds,
        tetrahedra_improved=run.mesh.tetrahedron_count,
        valid_improved=not validate3(run.mesh, volume=box.volume),
        failing_improved=kind_mask(report.failing_kinds),
    )


@attrs.frozen(slots=True)
class CensusSummary:
    """Counts over a set of rows of one shape, order and template: ``patterns``;
    ``valid`` (rows whose meshes are all valid); for each transformable kind the rows
    having one (``present[kind]``) and having a failing one (``failing[kind]``);
    ``delaunay`` (Delaunay as partitioned); tetrahedra totals; with the improvement:
    ``flips`` per kind, ``delaunay_improved``, ``failing_improved[kind]`` (rows whose
    improved mesh still fails across a face of that kind) and the largest ``rounds``."""

    shape: str
    order: str
    template: int
    patterns: int
    valid: int
    present: dict[str, int]
    failing: dict[str, int]
    delaunay: int
    tetrahedra: int
    tetrahedra_min: int
    tetrahedra_max: int
    improved: int
    flips: dict[str, int]
    delaunay_improved: int
    failing_improved: dict[str, int]
    tetrahedra_improved: int
    rounds_max: int

    def percent(self, count: int) -> float:
        return 100.0 * count / self.patterns if self.patterns else 0.0

    def report(self) -> dict[str, Any]:
        """The summary as JSON values (percentages rounded to 0.01)."""
        def pct(count: int) -> float:
            return round(self.percent(count), 2)

        out: dict[str, Any] = {
            "shape": self.shape, "order": self.order, "template": self.template,
            "patterns": self.patterns, "valid": self.valid,
            "delaunay": self.delaunay, "delaunay_percent": pct(self.delaunay),
            "present": dict(self.present),
            "present_percent": {k: pct(v) for k, v in self.present.items()},
            "failing": dict(self.failing),
            "failing_percent": {k: pct(v) for k, v in self.failing.items()},
            "tetrahedra_mean": round(self.tetrahedra / self.patterns, 4) if self.patterns
            else None,
            "tetrahedra_min": self.tetrahedra_min, "tetrahedra_max": self.tetrahedra_max,
            "improved": self.improved,
        }
        if self.improved:
            out.update({
                "flips": dict(self.flips),
                "delaunay_improved": self.delaunay_improved,
                "delaunay_improved_percent": pct(self.delaunay_improved),
                "failing_improved": dict(self.failing_improved),
                "failing_improved_percent": {k: pct(v)
                                             for k, v in self.failing_improved.items()},
                "tetrahedra_improved_mean": round(self.tetrahedra_improved / self.improved, 4),
                "rounds_max": self.rounds_max,
            })
        return out


def summarize(rows: Iterable[CensusRow]) -> list[CensusSummary]:
    """One summary per (shape, order, template) met in ``rows``, in order of appearance."""
    groups: dict[tuple[str, str, int], list[CensusRow]] = {}
    for row in rows:
        groups.setdefault((row.shape, row.order, row.template), []).append(row)
    return [_summary(key, members) for key, members in groups.items()]


def _count_kinds(masks: Counter[int]) -> dict[str, int]:
    """Kind name -> the number of rows whose mask has it (``masks``: mask -> rows)."""
    return {kind.value: sum(rows for mask, rows in masks.items() if mask & _BIT[kind.value])
            for kind in KIND_ORDER}


def _summary(key: tuple[str, str, int], rows: list[CensusRow]) -> CensusSummary:
    shape, order, template = key
    flips = dict.fromkeys(FLIP_NAMES, 0)
    improved = [row for row in rows if row.flips is not None]
    for row in improved:
        assert row.flips is not None
        for index, name in enumerate(FLIP_NAMES):
            flips[name] += row.flips[index]
    failing_after = Counter(row.failing_improved for row in improved)
    tetrahedra = [row.tetrahedra for row in rows]
    return CensusSummary(
        shape=shape, order=order, template=template, patterns=len(rows),
        valid=sum(row.valid and row.valid_improved is not False for row in rows),
        present=_count_kinds(Counter(row.kinds for row in rows)),
        failing=_count_kinds(Counter(row.failing for row in rows)),
        delaunay=sum(row.failing == 0 for row in rows),
        tetrahedra=sum(tetrahedra),
        tetrahedra_min=min(tetrahedra, default=0),
        tetrahedra_max=max(tetrahedra, default=0),
        improved=len(improved), flips=flips,
        delaunay_improved=failing_after.get(0, 0),
        failing_improved=_count_kinds(failing_after),  # type: ignore[arg-type]
        tetrahedra_improved=sum(row.tetrahedra_improved or 0 for row in improved),
        rounds_max=max((row.rounds or 0 for row in improved), default=0),
    )
