"""The 3D page of a three-material device in headless Chromium (issue 24): the MOS device
meshed and written with its materials, then ``geomexact view --color-by material``: the
page draws without errors, the legend lists the three materials, the statistics count each
one's cells, and the colour menu switches between material and the other modes."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from helpers.chromium import canvas_image, canvas_inked, open_offline_page
from helpers.device_cases import MOS_DEVICE

from geomexact.cli import main

pytestmark = pytest.mark.browser

ARTIFACTS = Path(__file__).resolve().parents[2] / "artifacts" / "browser"
MATERIALS = ("1", "2", "3")


@pytest.fixture(scope="module")
def folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder: Path = tmp_path_factory.mktemp("materials")
    return folder


@pytest.fixture(scope="module")
def cells(folder: Path, page: Any) -> dict[str, int]:
    """Each material's cell count in the written file."""
    from geomexact.io.cell_arrays import read_cell_arrays

    materials = read_cell_arrays(folder / "mos.vtu")["material"].tolist()
    return {m: materials.count(int(m)) for m in MATERIALS}


@pytest.fixture(scope="module")
def page(browser: Any, folder: Path) -> Iterator[tuple[Any, list[str], list[str]]]:
    pytest.importorskip("meshio")
    (folder / "mos.device").write_text(MOS_DEVICE)
    mesh, html = folder / "mos.vtu", folder / "mos.html"
    assert main(["octree", "--device", str(folder / "mos.device"), "--level", "1", "-o",
                 str(mesh), "--json"]) == 0
    assert main(["view", str(mesh), "-o", str(html), "--color-by", "material"]) == 0
    yield from open_offline_page(browser, html)


def test_draws_materials_with_a_legend(page: tuple[Any, list[str], list[str]],
                                       cells: dict[str, int]) -> None:
    tab, errors, requests = page
    assert canvas_inked(tab) > 20_000
    assert tab.input_value("#colour") == "material"
    legend = tab.inner_text("#legend")
    assert all(f"material {m}" in legend for m in MATERIALS)
    assert tab.locator("#legend li").count() == 3
    counts = tab.evaluate("() => document.getElementById('stats-table').dataset.materials")
    assert json.loads(counts) == cells and all(cells.values())
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    tab.screenshot(path=str(ARTIFACTS / "viewer3d-materials.png"))
    assert errors == []
    assert all(url.startswith("file://") for url in requests), requests


def test_colour_mode_material_is_selectable(page: tuple[Any, list[str], list[str]],
                                            cells: dict[str, int]) -> None:
    tab, errors, _ = page
    by_material = canvas_image(tab)
    tab.select_option("#colour", "quality")
    assert canvas_image(tab) != by_material
    assert "radius ratio" in tab.inner_text("#legend")
    tab.select_option("#colour", "material")
    assert canvas_image(tab) == by_material
    assert "material 3" in tab.inner_text("#legend")
    tab.select_option("#clip-axis", "z")
    tab.evaluate("""() => { const s = document.getElementById('clip');
        s.value = '600'; s.dispatchEvent(new Event('input')); }""")
    kept = json.loads(tab.evaluate(
        "() => document.getElementById('stats-table').dataset.materials"))
    assert kept.get("3", 0) == 0 and kept["1"] == cells["1"]
    assert errors == []
