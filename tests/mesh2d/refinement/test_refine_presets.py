"""Presets and named rules of ``refine`` (``geomexact.mesh2d.refinement.presets``): how a
preset and single overrides resolve, what each rule changes, that both Python engines
agree on them and the compiled kernel declines them, the trace parameters, the command's
flags, and the published-figure runs on Lake Superior."""

from __future__ import annotations

import json
import warnings
from importlib import resources
from pathlib import Path
from typing import Any

import pytest
from helpers.paths import read_superior

from geomexact.cli import main
from geomexact.errors import GeomexactDeprecationWarning, PreconditionError
from geomexact.kernel.numbers import mpq
from geomexact.kernel.points import point2
from geomexact.mesh2d.delaunay.triangulation import triangulate
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.refinement.api import refine
from geomexact.mesh2d.refinement.criteria import AverageAreaFactor, MinAngle
from geomexact.mesh2d.refinement.driver import RunOptions
from geomexact.mesh2d.refinement.engines.compiled import AVAILABLE, unsupported
from geomexact.mesh2d.refinement.presets import PRESETS, Rules, rules
from geomexact.mesh2d.refinement.regions import Whole
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh2d.validation import validate
from geomexact.trace.playback import replay


@pytest.fixture(scope="module")
def superior() -> Mesh2:
    pslg = read_superior()
    assert isinstance(pslg, PSLG)
    return triangulate(pslg).mesh


@pytest.fixture(scope="module")
def notch() -> Mesh2:
    """A small constrained Delaunay mesh with a notch (constraint edges of every kind)."""
    corners = [(0, 0), (8, 0), (8, 5), (5, 5), (4, 2), (3, 5), (0, 5)]
    pslg = PSLG(vertices=[point2(x, y) for x, y in corners],
                segments=[(i, (i + 1) % 7, 1) for i in range(7)])
    return triangulate(pslg).mesh


def test_presets_resolve_and_each_rule_overrides_alone() -> None:
    """A preset gives its rules; each option replaces one rule and keeps the others."""
    assert rules(None) == Rules()
    assert rules("pineda") == PRESETS["pineda"]
    mellado = rules("mellado", order="worst-first")
    assert (mellado.centroid, mellado.order) == ("vertices", "worst-first")
    assert mellado.second_longest_rule == PRESETS["mellado"].second_longest_rule
    assert rules(None, factor_stop="target").changed() == {"factor_stop": "target"}


def test_constraint_midpoints_is_a_deprecated_name_of_the_second_longest_rule() -> None:
    """``constraint_midpoints`` still works, with a warning at the caller's line naming
    ``second_longest_rule``, in ``rules`` and in ``refine``."""
    from geomexact.mesh2d.refinement.api import refine
    from geomexact.mesh2d.refinement.criteria import MaxArea
    from geomexact.mesh2d.transient import mesh_from_triangles

    for value, rule in ((True, "bisect-second"), (False, "centroid")):
        with pytest.warns(GeomexactDeprecationWarning, match="second_longest_rule") as caught:
            assert rules("pineda", constraint_midpoints=value).second_longest_rule == rule
        assert caught[0].filename == __file__
    square = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)])
    with pytest.warns(GeomexactDeprecationWarning, match="second_longest_rule") as caught:
        old = refine(square, MaxArea("1/16"), method="centroid", constraint_midpoints=False)
    assert caught[0].filename == __file__
    assert old.trace == refine(square, MaxArea("1/16"), method="centroid",
                               second_longest_rule="centroid").trace


@pytest.mark.parametrize("options", [
    {"preset": "triangle"}, {"order": "random"}, {"second_longest_rule": "nearest"},
    {"factor_stop": "never"}, {"centroid": "circumcentre"},
    {"constraint_midpoints": False, "second_longest_rule": "bisect-second"},
])
def test_unknown_or_contradicting_rules_are_refused(options: dict[str, Any]) -> None:
    """An unknown value or a contradiction is a PreconditionError naming it."""
    preset = options.pop("preset", None)
    with pytest.raises(PreconditionError), warnings.catch_warnings():
        warnings.simplefilter("ignore", GeomexactDeprecationWarning)
        rules(preset, **options)


@pytest.mark.parametrize("options", [
    {"order": "passes"},
    {"second_longest_rule": "bisect-longest"},
    {"preset": "mellado"},
    {"preset": "pineda"},
])
def test_python_engines_agree_on_every_rule(notch: Mesh2, options: dict[str, Any]) -> None:
    """The reference and the batch engine record the same trace; it replays; the result
    is valid.  Mellado's literal rule (bisect the longest edge) does not end here: a
    terminal triangle at the boundary is bisected at its interior longest edge again and
    again (specs/refine.md), so it runs under a step limit."""
    literal = options.get("second_longest_rule") == "bisect-longest"
    limit = 300 if literal else None
    runs = [refine(notch, MinAngle(28), method="quasi", engine=engine, max_steps=limit,
                   **options)
            for engine in ("reference", "python")]
    assert runs[0].trace.steps == runs[1].trace.steps
    assert runs[0].mesh == runs[1].mesh
    assert replay(runs[0].start, runs[0].trace) == runs[0].mesh
    assert not validate(runs[0].mesh)
    assert runs[0].status == ("step-limit" if literal else "complete")


def test_passes_and_worst_first_differ(superior: Mesh2) -> None:
    """The order is a real rule: on Superior at 30° the centroid method's traces differ."""
    first = refine(superior, MinAngle(30), method="centroid", centroid="vertices")
    passes = refine(superior, MinAngle(30), method="centroid", centroid="vertices",
                    order="passes")
    assert first.trace.steps != passes.trace.steps
    assert first.status == passes.status == "complete"


def test_factor_stop_per_target_finishes_the_target(notch: Mesh2) -> None:
    """factor_stop="target" checks the mean only after a refined triangle: never fewer
    steps than checking after every action, and the mean is reached either way."""
    action = refine(notch, AverageAreaFactor(mpq(1, 5)), method="centroid")
    target = refine(notch, AverageAreaFactor(mpq(1, 5)), method="centroid",
                    factor_stop="target")
    assert target.stats.steps >= action.stats.steps
    assert target.status == action.status == "complete"


@pytest.mark.parametrize("options", [
    {"order": "passes"}, {"second_longest_rule": "bisect-longest"},
    {"factor_stop": "target"}, {"centroid": "vertices"}, {"centroid": "midpoint"},
])
def test_the_kernel_runs_every_rule(notch: Mesh2, options: dict[str, Any]) -> None:
    """Issue 25: every rule of the presets runs compiled (it declined them), with the
    Python engine's steps, digests and result."""
    run = RunOptions(AverageAreaFactor(mpq(1, 4)), Whole(), "centroid", True,
                     rules(None, **options))
    if not AVAILABLE:
        pytest.skip("the compiled kernel is not built")
    assert unsupported(notch, run) is None
    compiled = refine(notch, AverageAreaFactor(mpq(1, 4)), method="centroid",
                      engine="compiled", **options)
    python = refine(notch, AverageAreaFactor(mpq(1, 4)), method="centroid",
                    engine="python", **options)
    assert compiled.trace.steps == python.trace.steps
    assert compiled.trace.digests == python.trace.digests
    assert compiled.mesh.digest == python.mesh.digest


def test_trace_records_the_preset_and_changed_rules_only(notch: Mesh2) -> None:
    """Default runs keep their old parameters; a preset adds its name and its rules."""
    plain = refine(notch, MinAngle(25), method="centroid")
    names = dict(plain.trace.parameters)
    assert "preset" not in names and "order" not in names
    mellado = dict(refine(notch, MinAngle(25), method="centroid",
                          preset="mellado").trace.parameters)
    assert mellado["preset"] == "mellado" and mellado["order"] == "passes"
    assert mellado["centroid"] == "vertices"


@pytest.mark.parametrize(("method", "triangles"), [("centroid", 3393), ("quasi", 3380)])
def test_mellado_preset_on_superior_at_35(
    superior: Mesh2, method: Any, triangles: int
) -> None:
    """The figures docs/papers.md reports (Mellado's tables: 3,197 and 3,193)."""
    result = refine(superior, MinAngle(35), method=method, preset="mellado")
    assert result.status == "complete"
    assert result.mesh.triangle_count == triangles


def test_command_preset_and_rule_flags(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """--preset with an override runs; --plain-centroids against another rule is one
    usage line (exit 2)."""
    source = resources.files("geomexact") / "data" / "superior.poly"
    with resources.as_file(source) as path:
        code = main(["refine", str(path), "--min-angle", "30", "--method", "quasi",
                     "--preset", "mellado", "--order", "worst-first", "--json"])
        report = json.loads(capsys.readouterr().out)
        assert code == 0 and report["status"] == "complete"
        code = main(["refine", str(path), "--min-angle", "30", "--plain-centroids",
                     "--second-longest-rule", "bisect-second"])
    err = capsys.readouterr().err
    assert code == 2 and "contradicts" in err and "Traceback" not in err


def test_quasi_with_midpoint_insertion(superior: Mesh2, notch: Mesh2) -> None:
    """centroid="midpoint": no centroid step, only bisections and flips; ends on Superior
    at 25° with every angle at least 25° (or left); every engine agrees (the compiled
    one runs it: issue 25)."""
    result = refine(superior, MinAngle(25), method="quasi", centroid="midpoint")
    assert result.status == "complete" and result.stats.centroids == 0
    assert result.mesh.triangle_count == 1819
    assert {step.op for step in result.trace.steps} == {"bisect", "flip"}
    engines = ("reference", "python", "compiled") if AVAILABLE else ("reference", "python")
    runs = [refine(notch, MinAngle(25), method="quasi", centroid="midpoint", engine=engine)
            for engine in engines]
    assert all(run.trace.steps == runs[0].trace.steps for run in runs)


def test_one_rules_record_runs_as_the_keywords() -> None:
    """``rules=`` (one record, from a preset and overrides) runs and records exactly what
    the keywords one by one do, preset name included; giving both is refused."""
    start = triangulate(read_superior()).mesh
    chosen = rules("mellado", order="worst-first")
    assert chosen.preset == "mellado" and chosen == rules(None, centroid="vertices")
    by_record = refine(start, MinAngle(28), method="quasi", rules=chosen)
    by_keywords = refine(start, MinAngle(28), method="quasi", preset="mellado",
                         order="worst-first")
    assert by_record.trace == by_keywords.trace
    assert dict(by_record.trace.parameters)["preset"] == "mellado"
    assert "preset" not in dict(refine(start, MinAngle(28), method="quasi",
                                       rules=Rules()).trace.parameters)
    with pytest.raises(PreconditionError, match="give the rules once"):
        refine(start, MinAngle(28), method="quasi", rules=chosen, centroid="area")
