"""Quality and size in one refinement (issue 26, item 1): ``AnyOf`` refines a triangle
while it fails any of its criteria (Triangle's ``-q30a0.01``): every triangle of the
result meets every criterion (exactly), but an angle in a sharp input corner, which no
refinement can raise -- and those triangles still meet the area; the trace replays; the
CLI takes the goals together."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from helpers.command import run
from helpers.paths import SHARED_DATA, SUPERIOR, read_superior
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact import io, mpq, point2, triangulate
from geomexact.errors import PreconditionError
from geomexact.kernel.angles import compare_angle
from geomexact.kernel.predicate_results import Comparison
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.refinement.api import refine
from geomexact.mesh2d.refinement.criteria import (
    AnyOf,
    AverageAreaFactor,
    MaxArea,
    MaxEdgeLength,
    MinAngle,
    doubled_area,
)
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.trace.playback import replay

SHARED = SHARED_DATA


def _problems(mesh: Mesh2, angle: MinAngle, area: object, left: object) -> list[str]:
    found = []
    for a, b, c in mesh.iter_triangles():
        p, q, r = mesh.point(a), mesh.point(b), mesh.point(c)
        if doubled_area(p, q, r) > 2 * area:  # type: ignore[operator]
            found.append(f"{(a, b, c)} is larger than {area}")
        if (a, b, c) in left:  # type: ignore[operator]
            continue
        for x, y, z in ((p, q, r), (q, r, p), (r, p, q)):
            if compare_angle(x, y, z, angle.threshold) == Comparison.LESS:
                found.append(f"{(a, b, c)} has an angle below {angle.degrees}")
    return found


def _superior() -> Mesh2:
    pslg = read_superior()
    assert isinstance(pslg, PSLG)
    return triangulate(pslg).mesh


def _square() -> Mesh2:
    corners = [point2(0, 0), point2(1, 0), point2(1, 1), point2(0, 1)]
    return triangulate(PSLG(vertices=corners, segments=[(0, 1, 1), (1, 2, 1), (2, 3, 1),
                                                        (3, 0, 1)])).mesh


@pytest.mark.parametrize(("make", "area"), [(_square, mpq(1, 100)), (_superior, mpq(1, 4))],
                         ids=["unit-square", "superior"])
def test_every_triangle_meets_the_angle_and_the_area(make: object, area: object) -> None:
    mesh = make()  # type: ignore[operator]
    angle = MinAngle(30)
    result = refine(mesh, AnyOf((angle, MaxArea(area))), method="centroid")
    assert result.stats.status == "complete"
    assert _problems(result.mesh, angle, area, set(result.stats.left)) == []
    assert set(result.stats.left_reasons) <= {"sharp-corner", "protected-tip"}
    assert replay(mesh, result.trace) == result.mesh
    # the combination needs at least what each criterion alone needs
    alone = refine(mesh, MaxArea(area), method="centroid").mesh.triangle_count
    assert result.mesh.triangle_count >= alone


@pytest.mark.skipif(not (SHARED / "polylla-refinement").is_dir(), reason="no ../shared")
def test_pikachu() -> None:
    mesh = io.read(SHARED / "polylla-refinement" / "pikachu_triangle.off")
    assert isinstance(mesh, Mesh2)
    angle, area = MinAngle(30), mpq(100_000)
    result = refine(mesh, AnyOf((angle, MaxArea(area))), method="centroid")
    assert _problems(result.mesh, angle, area, set(result.stats.left)) == []


@given(st.integers(20, 300))
@settings(max_examples=8, deadline=None)
def test_a_sharp_corner_still_meets_the_area(height: int) -> None:
    """Triangles whose small angle lies in a sharp input corner are left for the angle,
    not for the area."""
    points = [point2(0, 0), point2(10, 0), point2(12, 1), point2(10, mpq(height, 100))]
    mesh = triangulate(PSLG(vertices=points, segments=[(0, 1, 1), (1, 2, 1), (2, 3, 1),
                                                       (3, 0, 1)])).mesh
    angle, area = MinAngle(25), mpq(1, 2)
    result = refine(mesh, AnyOf((angle, MaxArea(area))), method="centroid")
    assert _problems(result.mesh, angle, area, set(result.stats.left)) == []


def test_what_does_not_combine_is_refused() -> None:
    with pytest.raises(PreconditionError, match="two or more"):
        AnyOf((MinAngle(30),))
    with pytest.raises(PreconditionError, match="region-wide"):
        AnyOf((MinAngle(30), AverageAreaFactor(mpq(1, 2))))
    with pytest.raises(PreconditionError, match="at most one minimum angle"):
        AnyOf((MinAngle(30), MinAngle(20)))
    both = AnyOf((MaxEdgeLength(1), MaxArea(1)))
    assert both.parameters()["kind"] == "any_of" and both.angle_threshold is None


def test_the_command_takes_the_goals_together(capsys: pytest.CaptureFixture[str],
                                              tmp_path: Path) -> None:
    path = SUPERIOR
    out = tmp_path / "s.ele"
    code, text, err = run(capsys, "refine", path, "--min-angle", "30", "--max-area",
                          "0.25", "-o", out, "--json", "--no-progress")
    assert code == 0, err
    report = json.loads(text)
    assert report["criterion"]["kind"] == "any_of"
    assert report["max_area"] <= 0.25 and report["status"] == "complete"
    code, _, err = run(capsys, "refine", path, "--min-angle", "30", "--factor", "0.5")
    assert code == 2 and "does not combine" in err
    code, _, err = run(capsys, "refine", path)
    assert code == 2 and "give a goal" in err


@pytest.mark.parametrize("method", ["centroid", "quasi", "bisection"])
def test_every_engine_gives_the_same_trace(method: str) -> None:
    """The reference ops, the Python engine and (for the minimum angle with the area,
    the combination the command makes) the compiled kernel: one trace, step by step."""
    mesh = _square()
    criterion = AnyOf((MinAngle(25), MaxArea(mpq(1, 50)))) if method != "bisection" else \
        AnyOf((MaxEdgeLength(mpq(1, 4)), MaxArea(mpq(1, 50))))
    engines = ["reference", "python", "compiled"]  # every combination compiled (issue 26)
    runs = [refine(mesh, criterion, method=method, engine=engine)  # type: ignore[arg-type]
            for engine in engines]
    for other in runs[1:]:
        assert other.mesh == runs[0].mesh
        assert other.trace.steps == runs[0].trace.steps
        assert other.trace.digests == runs[0].trace.digests
        assert other.stats.left == runs[0].stats.left


@pytest.mark.parametrize("method", ["centroid", "quasi"])
@pytest.mark.parametrize("height", [20, 60, 300])
def test_the_compiled_kernel_runs_angle_and_area_as_the_python_engine(method: str,
                                                                       height: int) -> None:
    """Sharp input corners (left for the angle, refined for the area), off-grid
    coordinates (the area rated in Python inside the kernel): the same trace."""
    points = [point2(0, 0), point2(10, 0), point2(12, 1), point2(10, mpq(height, 100)),
              point2(mpq(1, 3), mpq(7, 3))]
    mesh = triangulate(PSLG(vertices=points, segments=[(0, 1, 1), (1, 2, 1), (2, 3, 1),
                                                       (3, 4, 1), (4, 0, 1)])).mesh
    for criterion in (AnyOf((MinAngle(27), MaxArea(mpq(1, 3)))),
                      AnyOf((MinAngle(27), MaxEdgeLength(mpq(3, 2)))),
                      AnyOf((MaxEdgeLength(mpq(3, 2)), MaxArea(mpq(1, 3)))),
                      AnyOf((MinAngle(27), MaxArea(mpq(1, 3)), MaxEdgeLength(mpq(3, 2))))):
        compiled = refine(mesh, criterion, method=method,  # type: ignore[arg-type]
                          engine="compiled")
        python = refine(mesh, criterion, method=method,  # type: ignore[arg-type]
                        engine="python")
        assert compiled.trace.steps == python.trace.steps
        assert compiled.trace.digests == python.trace.digests
        assert compiled.stats.left == python.stats.left and compiled.mesh == python.mesh
        assert compiled.stats.left_reasons == python.stats.left_reasons


TWO_REGIONS = """# two squares side by side, the right one with a small maximum area
6 2 0 1
1 0 0 1
2 1 0 1
3 2 0 1
4 2 1 1
5 1 1 1
6 0 1 1
7 1
1 1 2 1
2 2 3 1
3 3 4 1
4 4 5 1
5 5 6 1
6 6 1 1
7 2 5 1
0
2
1 0.5 0.5 1 0.1
2 1.5 0.5 2 0.001
"""


def _largest_by_region(mesh: Mesh2) -> dict[object, object]:
    largest: dict[object, object] = {}
    for triangle in mesh.iter_triangles():
        attribute = mesh.triangle_attributes.get(triangle)
        area = doubled_area(*(mesh.point(v) for v in triangle)) / 2
        largest[attribute] = max(largest.get(attribute, 0), area)  # type: ignore[call-overload]
    return largest


def test_region_areas_from_a_poly_region_list(tmp_path: Path) -> None:
    """Triangle's -a without a number: each region to its own maximum area, alone or with
    a minimum angle."""
    from geomexact.mesh2d.refinement.criteria import RegionAreas, region_areas_of

    path = tmp_path / "two.poly"
    path.write_text(TWO_REGIONS)
    pslg = io.read(path)
    assert isinstance(pslg, PSLG)
    areas = region_areas_of(pslg)
    assert areas.areas == ((1, mpq(1, 10)), (2, mpq(1, 1000)))
    mesh = triangulate(pslg).mesh
    for criterion in (areas, AnyOf((MinAngle(25), areas))):
        result = refine(mesh, criterion, method="centroid")
        largest = _largest_by_region(result.mesh)
        assert largest[(1,)] <= mpq(1, 10) and largest[(2,)] <= mpq(1, 1000)  # type: ignore[operator]
        assert replay(mesh, result.trace) == result.mesh
    with pytest.raises(PreconditionError, match="different maximum areas"):
        RegionAreas(((1, mpq(1, 10)), (1, mpq(1, 5))))


def test_the_command_reads_region_areas(capsys: pytest.CaptureFixture[str],
                                        tmp_path: Path) -> None:
    path = tmp_path / "two.poly"
    path.write_text(TWO_REGIONS)
    code, text, err = run(capsys, "refine", path, "--region-areas", "--min-angle", "25", "-o",
                          tmp_path / "out.ele", "--json", "--no-progress")
    assert code == 0, err
    assert json.loads(text)["criterion"]["kind"] == "any_of"
    largest = _largest_by_region(io.read(tmp_path / "out.ele"))  # type: ignore[arg-type]
    assert largest[(2,)] <= mpq(1, 1000)  # type: ignore[operator]
    plain = tmp_path / "plain.poly"
    plain.write_text(TWO_REGIONS.replace(" 0.1\n", " -1\n").replace(" 0.001\n", " -1\n"))
    code, _, err = run(capsys, "refine", plain, "--region-areas")
    assert code == 2 and "needs a PSLG whose region list" in err
