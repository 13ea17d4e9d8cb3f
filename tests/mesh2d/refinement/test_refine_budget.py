"""The default step budget (``geomexact.mesh2d.refinement.budget``): its formula, the status
``"budget"`` it gives a run that does not end, ``max_steps=None`` lifting it, and the
command's exit code 3 with a one-line message."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from geomexact import io
from geomexact.cli import main
from geomexact.kernel.numbers import mpq
from geomexact.mesh2d.refinement.api import refine
from geomexact.mesh2d.refinement.budget import default_budget, estimated_triangles
from geomexact.mesh2d.refinement.criteria import (
    AverageAreaFactor,
    CallableCriterion,
    MaxArea,
    MaxEdgeLength,
    MinAngle,
    RegionAreas,
)
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh2d.transient import mesh_from_triangles

COUNTEREXAMPLE = Path(__file__).parents[2] / "data" / "nonterminating" / \
    "quasi-vertices-plain-34.off"


@pytest.fixture
def square() -> Mesh2:
    return mesh_from_triangles([(0, 0), (2, 0), (2, 2), (0, 2)], [(0, 1, 2), (0, 2, 3)])


@pytest.fixture(scope="module")
def counterexample() -> Mesh2:
    mesh = io.read(COUNTEREXAMPLE)
    assert isinstance(mesh, Mesh2)
    return mesh


def test_estimate_follows_the_documented_formula(square: Mesh2) -> None:
    """E = ⌈2|Ω|/A⌉, ⌈4|Ω|/L²⌉, ⌈T/f⌉, and 0 for an angle or a callable (|Ω| = 4)."""
    assert estimated_triangles(square, MaxArea(mpq(3, 10))) == 27  # ⌈8 / 0.3⌉
    assert estimated_triangles(square, MaxEdgeLength(mpq(1, 2))) == 64  # 16 / (1/4)
    assert estimated_triangles(square, AverageAreaFactor(mpq(1, 3))) == 6
    assert estimated_triangles(square, MinAngle(30)) == 0
    assert estimated_triangles(square, CallableCriterion(lambda a, b, c: False)) == 0
    assert default_budget(square, MaxArea(mpq(3, 10))) == 100 * (2 + 27) + 10_000


def test_a_run_that_does_not_end_stops_at_the_budget(counterexample: Mesh2) -> None:
    """The 3-triangle counterexample of quasi + four-vertex mean + plain centroids at 34°
    stops at exactly the default budget with status "budget", listing what it left."""
    result = refine(counterexample, MinAngle(34), method="quasi", centroid="vertices",
                    second_longest_rule="centroid")
    budget = default_budget(counterexample, MinAngle(34))
    assert result.status == "budget"
    assert result.stats.steps == budget == 10_300
    assert result.stats.waiting
    assert result.trace.parameter("step_budget") == budget
    assert result.trace.parameter("max_steps") is None
    summary = result.stats.left_summary()
    assert summary is not None and "default step budget" in summary


@pytest.mark.parametrize("centroid", ["area", "vertices"])
def test_the_counterexample_ends_with_constraint_midpoints(
    counterexample: Mesh2, centroid: str
) -> None:
    """The same input ends with the constraint-midpoint rule (the default): the
    non-termination is the plain-centroid rule's, not the input's."""
    result = refine(counterexample, MinAngle(34), method="quasi",
                    centroid=centroid)  # type: ignore[arg-type]
    assert result.status == "complete"


def test_an_explicit_limit_keeps_status_step_limit(counterexample: Mesh2) -> None:
    """max_steps=N stops with "step-limit" and records no budget."""
    result = refine(counterexample, MinAngle(34), method="quasi", centroid="vertices",
                    second_longest_rule="centroid", max_steps=50)
    assert result.status == "step-limit" and result.stats.steps == 50
    assert result.trace.parameter("step_budget") is None
    assert result.trace.parameter("max_steps") == 50


def test_no_limit_records_none(square: Mesh2) -> None:
    """max_steps=None: no budget, the run ends by itself here."""
    result = refine(square, MaxArea(mpq(1, 8)), max_steps=None)
    assert result.status == "complete"
    assert result.trace.parameter("step_budget") is None


def test_command_exits_3_with_one_line_and_writes_the_partial_mesh(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """refine at the budget: exit code 3, one stderr line naming the budget and
    --max-steps none, the mesh written, status "budget" in the JSON."""
    out_path = tmp_path / "out.off"
    code = main(["refine", str(COUNTEREXAMPLE), "--min-angle", "34", "--method", "quasi",
                 "--centroid", "vertices", "--plain-centroids", "-o", str(out_path),
                 "--json"])
    out, err = capsys.readouterr()
    assert code == 3
    assert json.loads(out)["status"] == "budget"
    assert out_path.exists()
    lines = [line for line in err.splitlines() if "stopped at its default step budget" in line]
    assert len(lines) == 1 and "--max-steps none" in lines[0]
    assert "Traceback" not in err


def test_command_max_steps_none_and_a_number(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """--max-steps none lifts the budget (a run that ends exits 0); --max-steps 5 stops
    with step-limit and exit 0; a bad value is one usage line, exit 2."""
    square = tmp_path / "square.off"
    io.write(square, mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)],
                                         [(0, 1, 2), (0, 2, 3)]))
    assert main(["refine", str(square), "--max-area", "1/64", "--max-steps", "none",
                 "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["status"] == "complete"
    assert main(["refine", str(square), "--max-area", "1/64", "--max-steps", "5",
                 "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["status"] == "step-limit"
    assert main(["refine", str(square), "--max-area", "1/64", "--max-steps", "lots"]) == 2
    err = capsys.readouterr().err
    assert "--max-steps" in err and "Traceback" not in err


def test_region_areas_estimate_each_region_by_its_own_area() -> None:
    """RegionAreas: Σ ⌈2·|Ωᵢ| / Aᵢ⌉ over its regions (a region of no listed area and a
    triangle without attributes count nothing); before, 0, and a --region-areas run of
    86,403 triangles stopped at 10,400 steps."""
    mesh = mesh_from_triangles(
        [(0, 0), (1, 0), (2, 0), (2, 1), (1, 1), (0, 1)],
        [(0, 1, 4), (0, 4, 5), (1, 2, 3), (1, 3, 4)],
        triangle_attributes=[(mpq(1),), (mpq(1),), (mpq(2),), (mpq(5),)])
    areas = RegionAreas(((mpq(1), mpq(1, 100)), (mpq(2), mpq(1, 30)), (mpq(3), mpq(1))))
    # region 1: area 1 -> 200; region 2: area 1/2 -> 30; regions 3 and 5: nothing
    assert estimated_triangles(mesh, areas) == 230
    result = refine(mesh, areas)
    assert result.status == "complete"


def test_the_estimate_is_summed_once_for_the_command_and_refine(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """The command's memory budget and refine()'s step budget ask for the same estimate:
    the O(T) exact sum runs once (issue 25: it ran twice)."""
    from geomexact.mesh2d.refinement import budget

    calls = []
    original = budget.doubled_area

    def counting(*points: object) -> object:
        calls.append(1)
        return original(*points)  # type: ignore[arg-type]

    monkeypatch.setattr(budget, "doubled_area", counting)
    mesh = mesh_from_triangles([(0, 0), (3, 0), (3, 3), (0, 3)], [(0, 1, 2), (0, 2, 3)])
    criterion = MaxArea(mpq(1, 7))
    first = estimated_triangles(mesh, criterion)
    assert calls == [1, 1]
    assert estimated_triangles(mesh, MaxArea(mpq(1, 7))) == first == 126
    assert calls == [1, 1]  # the same mesh and an equal criterion: not summed again
    assert estimated_triangles(mesh, MaxArea(mpq(1, 5))) == 90 and len(calls) == 4
