"""``info`` and ``check`` on a three-material device mesh (issue 24): the materials of the
``material`` cell array, each with its cells and its exact volume."""

from __future__ import annotations

import json
from fractions import Fraction
from pathlib import Path

import pytest
from helpers.command import run
from helpers.device_cases import MOS_DEVICE

pytest.importorskip("meshio")

VOLUMES = {"1": Fraction(1, 2), "2": Fraction(1, 4), "3": Fraction(1, 16)}


@pytest.fixture(scope="module")
def mos(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The MOS device meshed at level 1 and written with its materials."""
    from geomexact.cli import main

    folder = tmp_path_factory.mktemp("mos")
    device = folder / "mos.device"
    device.write_text(MOS_DEVICE)
    output = folder / "mos.vtu"
    assert main(["octree", "--device", str(device), "--level", "1", "-o", str(output),
                 "--json"]) == 0
    return output


def test_info_json_reports_exact_material_volumes(
        mos: Path, capsys: pytest.CaptureFixture[str]) -> None:
    capsys.readouterr()
    code, out, _ = run(capsys, "info", mos, "--json")
    assert code == 0
    report = json.loads(out)
    assert report["material_array"] == "material"
    materials = report["materials"]
    assert {m: Fraction(row["volume"]) for m, row in materials.items()} == VOLUMES
    assert sum(row["cells"] for row in materials.values()) == report["tetrahedra"]
    assert sum(VOLUMES.values()) == Fraction(report["volume"])


def test_info_and_check_text_list_each_material(
        mos: Path, capsys: pytest.CaptureFixture[str]) -> None:
    capsys.readouterr()
    code, out, _ = run(capsys, "info", mos)
    assert code == 0
    assert "material array  material" in out
    assert "material 3: " in out and "volume 0.0625" in out
    code, out, _ = run(capsys, "check", mos)
    assert code == 0 and "valid" in out
    assert "material 1: " in out and "volume 0.5" in out
    code, out, _ = run(capsys, "check", mos, "--json")
    report = json.loads(out)
    assert {m: Fraction(row["volume"]) for m, row in report["materials"].items()} == VOLUMES


def test_files_without_materials_report_none(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from helpers.mesh3d_cases import cube_grid

    from geomexact import io

    path = tmp_path / "grid.vtu"
    io.write(path, cube_grid(1, 1, 1))
    code, out, _ = run(capsys, "info", path, "--json")
    assert code == 0 and "materials" not in json.loads(out)
