"""An independent check of ``validate_mixed``: planarity, face and cell convexity, cell
volumes, face matching and the total volume recomputed with ``fractions.Fraction`` only
(no geomexact geometry), on a few hundred random meshes (box grids, random splits and
merges, then sometimes a moved vertex, an inverted cell or a dropped cell), agreeing with
the checker cell by cell."""

from __future__ import annotations

import random
from collections import Counter
from fractions import Fraction

import pytest
from helpers.fraction_cells import CELL_KINDS, first_problem, volume
from helpers.mixed_cases import random_grid, random_walk

from geomexact.mesh3d.mixed.cells import cell_of_faces
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.mixed.transient import mixed_mesh_from_cells
from geomexact.mesh3d.mixed.validation import validate_mixed


def independent_view(mesh: MixedMesh3) -> tuple[dict[tuple[int, ...], set[str]], Fraction,
                                                  int, int]:
    points = {v: tuple(Fraction(int(c.numerator), int(c.denominator)) for c in p[:3])
              for v, p in mesh.vertices.items()}
    problems = {}
    total = Fraction(0)
    polygons: Counter[frozenset[int]] = Counter()
    directed: Counter[tuple[int, ...]] = Counter()
    for cell in mesh.cell_list():
        problems[cell.vertices] = first_problem(cell.faces, points)  # type: ignore[arg-type]
        total += volume(cell.faces, points)  # type: ignore[arg-type]
        for face in cell.faces:
            start = face.index(min(face))
            directed[face[start:] + face[:start]] += 1
    for face, times in directed.items():
        back = tuple(reversed(face))
        start = back.index(min(back))
        if directed.get(back[start:] + back[:start]) == 1 and times == 1:
            polygons[frozenset(face)] += 1
    same_side = sum(1 for times in directed.values() if times > 1)
    return problems, total, len(polygons), same_side


def corrupt(mesh: MixedMesh3, rng: random.Random) -> MixedMesh3:
    choice = rng.randrange(4)
    cells = mesh.cell_list()
    points = [mesh.point(v) for v in range(mesh.vertex_count)]
    if choice == 1:
        v = rng.randrange(len(points))
        p = points[v]
        points[v] = (p.x + Fraction(rng.randint(-2, 2), rng.randint(1, 5)), p.y,  # type: ignore[assignment]
                     p.z + Fraction(rng.randint(-1, 1), 3))
    elif choice == 2:
        k = rng.randrange(len(cells))
        cells[k] = cell_of_faces([tuple(reversed(f)) for f in cells[k].faces])
    elif choice == 3 and len(cells) > 1:
        cells.pop(rng.randrange(len(cells)))
    return mixed_mesh_from_cells(points, cells)


@pytest.mark.parametrize("seed", range(300))
def test_validate_mixed_agrees_with_an_independent_fraction_check(seed: int) -> None:
    rng = random.Random(seed)
    box, start = random_grid(rng, largest=2)
    transient = start.transient()
    random_walk(transient, rng, rng.randint(0, 6))
    mesh = corrupt(transient.seal(), rng)
    found = validate_mixed(mesh, volume=box.volume)
    problems, total, _, same_side = independent_view(mesh)
    reported: dict[tuple[int, ...], set[str]] = {}
    for violation in found:
        if violation.kind in CELL_KINDS:
            reported.setdefault(violation.elements, set()).add(violation.kind)
    for vertices, kinds in problems.items():
        assert reported.get(vertices, set()) == kinds, (vertices, kinds)
    assert ("volume-mismatch" in {v.kind for v in found}) == (total != box.volume)
    assert ("face-orientation" in {v.kind for v in found}) == (same_side > 0)
    if not any(problems.values()) and total == box.volume and same_side == 0:
        # nothing changed, or a moved vertex kept every cell convex: still valid
        assert found == []
