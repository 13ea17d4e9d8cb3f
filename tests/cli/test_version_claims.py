"""``geomexact --version`` says exactly which runs the compiled Lepp kernel takes: the
claim in ``cli.parser.KERNEL_RUNS`` is checked here against the kernel's own ``unsupported``
over every method, centroid kind, criterion, flip setting and attribute case."""

from __future__ import annotations

import itertools

import pytest

from geomexact import mesh_from_triangles, mpq
from geomexact.cli.parser import KERNEL_RUNS, version_text
from geomexact.mesh2d.refinement import criteria
from geomexact.mesh2d.refinement.driver import RunOptions
from geomexact.mesh2d.refinement.engines import compiled as compiled_engine
from geomexact.mesh2d.refinement.presets import rules
from geomexact.mesh2d.refinement.regions import Circle, Whole
from geomexact.mesh2d.transient import Transient2

SQUARE = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)])
CRITERIA = {
    "--max-area": criteria.MaxArea(mpq(1, 8)),
    "--factor": criteria.AverageAreaFactor(mpq(1, 2)),
    "--max-edge": criteria.MaxEdgeLength(mpq(1, 2)),
    "--min-angle": criteria.MinAngle(mpq(30)),
}


def _attributed() -> object:
    transient = Transient2(SQUARE)
    transient.set_triangle_attributes((0, 1, 2), (mpq(1),))
    return transient.seal()


@pytest.mark.skipif(not compiled_engine.AVAILABLE, reason="the Lepp kernel is not built")
def test_the_lepp_claim_is_what_the_kernel_runs() -> None:
    claim = dict(KERNEL_RUNS)["lepp"]
    for option in ("--max-area", "--factor", "--max-edge", "--min-angle",
                   "--method bisection, centroid or quasi", "every --centroid",
                   "--no-delaunay", "--plain-centroids", "every --preset",
                   "with triangle or vertex attributes", "--region-areas"):
        assert option in claim
    meshes = {"plain": SQUARE, "attributed": _attributed()}
    for method, centroid, name, delaunay, midpoints, region, kind in itertools.product(
        ("bisection", "centroid", "quasi"), ("area", "area-exact", "vertices"), CRITERIA,
        (True, False), (True, False), (Whole(), Circle(0, 0, 1)), meshes,
    ):
        run = RunOptions(CRITERIA[name], region, method, delaunay,  # type: ignore[arg-type]
                         rules(None, centroid=centroid, second_longest_rule=(
                             "bisect-second" if midpoints else "centroid")))
        runs = compiled_engine.unsupported(meshes[kind], run) is None
        claimed = True  # every method, centroid and attribute case (issue 25)
        assert runs == claimed, (method, centroid, name, delaunay, midpoints, kind)


def test_version_lists_each_built_kernel_with_what_it_runs() -> None:
    lines = version_text().splitlines()
    if compiled_engine.AVAILABLE:
        assert any(line.startswith("  lepp: refine --method") for line in lines)
    else:
        assert not any(line.startswith("  lepp:") for line in lines)


@pytest.mark.skipif(not compiled_engine.AVAILABLE, reason="the Lepp kernel is not built")
def test_the_claimed_combinations_run_compiled() -> None:
    """'the sizes together, with or without --min-angle': every AnyOf of the sizes, with
    the angle first or without it, runs compiled; the angle after a size does not."""
    sizes = [CRITERIA["--max-area"], CRITERIA["--max-edge"]]
    angle = CRITERIA["--min-angle"]
    for members in ([*sizes], [angle, sizes[0]], [angle, sizes[1]], [angle, *sizes]):
        run = RunOptions(criteria.AnyOf(tuple(members)), Whole(), "centroid", True,
                         rules(None))
        assert compiled_engine.unsupported(SQUARE, run) is None, members
    run = RunOptions(criteria.AnyOf((sizes[0], angle)), Whole(), "centroid", True,
                     rules(None))
    assert compiled_engine.unsupported(SQUARE, run) is not None
