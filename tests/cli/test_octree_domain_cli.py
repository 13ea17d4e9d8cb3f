"""``geomexact octree --domain`` (issue 24): a part with a hole meshed, checked and written
exactly; the trace replays to the same file; the same mesh in another process; bad
surfaces and options refused with nothing written."""

from __future__ import annotations

import json
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from helpers.command import run
from helpers.device_cases import MOS_DEVICE
from helpers.paths import SHARED_DATA
from helpers.surface_cases import cube, notched_box, torus, write_obj, write_off

from geomexact import io
from geomexact.kernel.numbers import parse_rational
from geomexact.mesh3d.measures import total_volume
from geomexact.mesh3d.surface.value import triangle_surface

SURFACES = SHARED_DATA / "surfaces"


@pytest.fixture()
def part(tmp_path: Path) -> Path:
    return write_obj(tmp_path / "part.obj", notched_box())


def test_a_part_is_meshed_checked_and_written(capsys: pytest.CaptureFixture[str],
                                              tmp_path: Path, part: Path) -> None:
    out, trace, start = tmp_path / "p.ele", tmp_path / "p.trace", tmp_path / "s.ele"
    code, text, err = run(capsys, "octree", "--domain", part, "--level", "4", "-o", out,
                          "--exact", "--trace", trace, "--start", start, "--json")
    assert code == 0, err
    report = json.loads(text)
    assert report["valid"] is True and report["boundary_on_surface"] is True
    assert report["problems"] == [] and report["tetrahedra"] > 100
    assert parse_rational(report["enclosed_volume"]) == notched_box().enclosed_volume()
    mesh = io.read(out)
    assert mesh.digest_text == report["digest"]  # type: ignore[union-attr]
    assert total_volume(mesh) == parse_rational(report["volume"])  # type: ignore[arg-type]
    assert report["steps"] == report["tetrahedra"]
    code, text, err = run(capsys, "replay", start, trace, "-o", tmp_path / "r.ele", "--exact",
                          "--json")
    assert code == 0, err
    assert json.loads(text)["final_digest"] == report["digest"]
    assert (tmp_path / "r.ele").read_bytes() == out.read_bytes()


def test_a_nested_surface_is_a_hole(capsys: pytest.CaptureFixture[str],
                                    tmp_path: Path) -> None:
    outer = write_off(tmp_path / "outer.off", cube(Fraction(0), Fraction(4)))
    inner = write_obj(tmp_path / "inner.obj", cube(Fraction(3, 2), Fraction(1)))
    # at level 4 the leaves are 1/2 wide: both cubes lie on the lattice, met exactly
    code, text, err = run(capsys, "octree", "--domain", outer, "--domain", inner, "--level",
                          "4", "--json")
    assert code == 0, err
    report = json.loads(text)
    assert report["enclosed_volume"] == "63" and report["volume"] == "63"
    assert report["valid"] is True


def test_the_mesh_is_the_same_in_another_process(capsys: pytest.CaptureFixture[str],
                                                 tmp_path: Path) -> None:
    path = write_obj(tmp_path / "torus.obj", torus())
    code, text, _ = run(capsys, "octree", "--domain", path, "--level", "4", "--json")
    assert code == 0
    other = subprocess.run([sys.executable, "-m", "geomexact", "octree", "--domain", str(path),
                            "--level", "4", "--json"], capture_output=True, text=True,
                           check=True, env={"PYTHONHASHSEED": "123", "PATH": ""})
    assert json.loads(other.stdout)["digest"] == json.loads(text)["digest"]


def test_bad_surfaces_and_options_are_refused(capsys: pytest.CaptureFixture[str],
                                              tmp_path: Path, part: Path) -> None:
    open_surface = cube()
    opened = triangle_surface(open_surface.points, open_surface.triangles[:-1], "open")
    bad = write_obj(tmp_path / "open.obj", opened)
    out = tmp_path / "o.ele"
    code, _, err = run(capsys, "octree", "--domain", bad, "-o", out)
    assert code == 2 and "open.obj" in err and "not closed" in err
    crossing = write_obj(tmp_path / "crossing.obj", cube(Fraction(1, 2), Fraction(1)))
    whole = write_obj(tmp_path / "whole.obj", cube())
    code, _, err = run(capsys, "octree", "--domain", whole, "--domain", crossing, "-o", out)
    assert code == 2 and "meet" in err
    code, _, err = run(capsys, "octree", "--domain", part, "--final", "mixed", "-o", out)
    assert code == 2 and "tetrahedra are fitted" in err
    code, _, err = run(capsys, "octree", "--domain", part, "--refine-sphere", "0", "0", "0",
                       "1", "-o", out)
    assert code == 2 and "--refine-sphere" in err
    code, _, err = run(capsys, "octree", "--band", "1/2")
    assert code == 2 and "--domain" in err
    assert not any(tmp_path.glob("o.*"))


def test_an_inward_surface_is_turned_and_said(capsys: pytest.CaptureFixture[str],
                                              tmp_path: Path) -> None:
    inward = write_obj(tmp_path / "in.obj", cube().reversed())
    code, text, err = run(capsys, "octree", "--domain", inward, "--level", "2", "--json")
    assert code == 0 and "faced inward" in err
    assert json.loads(text)["volume"] == "1"


@pytest.mark.skipif(not SURFACES.is_dir(), reason="../shared/data/surfaces is absent")
def test_spot_is_meshed(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    code, text, err = run(capsys, "octree", "--domain", SURFACES / "spot.obj", "--level",
                          "5", "--json")
    assert code == 0, err
    report = json.loads(text)
    assert report["valid"] and report["boundary_on_surface"] and report["min_dihedral"] > 5
    assert report["volume_error"] < 0.1




def test_a_device_is_meshed_with_its_materials(capsys: pytest.CaptureFixture[str],
                                               tmp_path: Path) -> None:
    meshio = pytest.importorskip("meshio")
    device = tmp_path / "mos.device"
    device.write_text(MOS_DEVICE)
    out = tmp_path / "mos.vtu"
    code, text, err = run(capsys, "octree", "--device", device, "--level", "1", "-o", out,
                          "--json")
    assert code == 0, err
    report = json.loads(text)
    assert report["valid"] is True and report["grid"] == [3, 3, 3]
    assert {m: (row["volume"], row["exact"]) for m, row in report["materials"].items()} == {
        "1": ("0.5", True), "2": ("0.25", True), "3": ("0.0625", True)}
    read = meshio.read(out)
    materials = np.concatenate([np.asarray(block) for block in read.cell_data["material"]])
    assert sorted(set(materials.tolist())) == [1, 2, 3]
    assert len(materials) == report["cells"]
    code, text, _ = run(capsys, "octree", "--device", device)
    assert code == 0 and "material 3 (metal)" in text and "(exact)" in text


def test_device_refusals_write_nothing(capsys: pytest.CaptureFixture[str],
                                       tmp_path: Path) -> None:
    device = tmp_path / "d.device"
    device.write_text(MOS_DEVICE.replace("0.75 0.75 1 3", "0.75 0.75 0.75 3"))
    code, _, err = run(capsys, "octree", "--device", device, "-o", tmp_path / "o.vtu")
    assert code == 2 and "d.device:8" in err and "Z0 < Z1" in err
    device.write_text(MOS_DEVICE)
    code, _, err = run(capsys, "octree", "--device", device, "-o", tmp_path / "o.ele")
    assert code == 2 and "not a mixed mesh" in err
    code, _, err = run(capsys, "octree", "--device", device, "--trace", tmp_path / "t")
    assert code == 2 and "--trace" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d.device"]


def test_quality_improvement_is_traced_from_the_fitted_mesh(
        capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    path = write_obj(tmp_path / "part.obj", notched_box())
    out, trace, start = tmp_path / "q.ele", tmp_path / "q.trace", tmp_path / "fit.ele"
    code, text, err = run(capsys, "octree", "--domain", path, "--level", "4", "--no-warp",
                          "--improve-quality", "15", "-o", out, "--exact", "--trace", trace,
                          "--start", start, "--json")
    assert code == 0, err
    report = json.loads(text)
    improvement = report["improvement"]
    assert improvement["flips"] > 0 and improvement["worst_after"] >= improvement["worst_before"]
    assert improvement["failing_after"] < improvement["failing_before"]
    assert report["valid"] and report["boundary_on_surface"]
    code, text, _ = run(capsys, "octree", "--domain", path, "--level", "4", "--no-warp",
                        "--json")
    assert json.loads(text)["volume"] == report["volume"]  # flips keep the volume exactly
    code, _, err = run(capsys, "replay", start, trace, "-o", tmp_path / "r.ele", "--exact")
    assert code == 0, err
    assert (tmp_path / "r.ele").read_bytes() == out.read_bytes()
    code, _, err = run(capsys, "octree", "--improve-quality", "15")
    assert code == 2 and "--domain" in err


def test_leaves_too_coarse_for_the_domain_write_nothing(capsys: pytest.CaptureFixture[str],
                                                        tmp_path: Path) -> None:
    path = write_obj(tmp_path / "c.obj", cube())
    code, out, err = run(capsys, "octree", "--domain", path, "--level", "0", "-o",
                         tmp_path / "c.ele")
    assert code == 1 and "too coarse" in out and "nothing was written" in err
    assert not any(tmp_path.glob("c.e*")) and not (tmp_path / "c.node").exists()
