"""The 3D page of a mixed-cell mesh in headless Chromium: a box grid with a wedge, a
pyramid, tetrahedra and polyhedra (one with pentagons) draws without errors, reports its
cells by kind, paints quads and pentagons as such, and the clip plane keeps whole cells and
changes what is drawn."""

from __future__ import annotations

import json
from collections import Counter
from collections.abc import Iterator
from fractions import Fraction
from pathlib import Path
from typing import Any

import pytest
from helpers.chromium import canvas_image, canvas_inked, open_offline_page
from helpers.mixed_view_cases import every_kind_mesh

from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.viz.scene3d import KIND_ORDER, KIND_PLURALS, viewer_html_3d

pytestmark = pytest.mark.browser

ARTIFACTS = Path(__file__).resolve().parents[2] / "artifacts" / "browser"


@pytest.fixture(scope="module")
def mesh() -> MixedMesh3:
    return every_kind_mesh()


@pytest.fixture(scope="module")
def page(browser: Any, mesh: MixedMesh3, tmp_path_factory: pytest.TempPathFactory
         ) -> Iterator[tuple[Any, list[str], list[str]]]:
    path: Path = tmp_path_factory.mktemp("mixed") / "mixed.html"
    path.write_text(viewer_html_3d(mesh, title="every kind"), encoding="utf-8")
    yield from open_offline_page(browser, path)


def _dataset(tab: Any, name: str) -> str:
    value: str = tab.evaluate(
        f"() => document.getElementById('stats-table').dataset.{name}")
    return value


def _kinds(cells: list[Any]) -> dict[str, int]:
    counts = Counter(cell.kind for cell in cells)
    return {KIND_PLURALS[kind]: counts[kind] for kind in KIND_ORDER if counts[kind]}


def _move_clip(tab: Any, value: int) -> None:
    tab.evaluate(f"""() => {{ const s = document.getElementById('clip');
        s.value = '{value}'; s.dispatchEvent(new Event('input')); }}""")


def test_draws_the_cells_by_kind(page: tuple[Any, list[str], list[str]],
                                 mesh: MixedMesh3) -> None:
    """The counts by kind, the exact volume and the digest are on the page; the legend
    names every kind; quads and pentagons are painted whole (no triangle fan)."""
    tab, errors, requests = page
    assert canvas_inked(tab) > 20_000
    assert json.loads(_dataset(tab, "kinds")) == _kinds(mesh.cell_list())
    assert int(_dataset(tab, "cells")) == mesh.cell_count == 21
    stats = tab.inner_text("#stats-table")
    assert "hexahedra" in stats and "wedges" in stats and "pyramids" in stats
    assert Fraction(tab.evaluate("() => JSON.parse(document.getElementById("
                                 "'geomexact-data').textContent).volume")) == Fraction(37, 36)
    assert mesh.digest_text in stats
    legend = tab.inner_text("#legend")
    assert all(name in legend for name in ("tetrahedra", "pyramids", "wedges", "hexahedra",
                                           "polyhedra"))
    sizes = tab.evaluate("() => geomexactView3d.frame.sizes")
    assert int(sizes.get("4", 0)) > 10
    assert tab.input_value("#colour") == "kind"
    assert tab.locator("#colour option[value=quality]").count() == 0
    tab.screenshot(path=str(ARTIFACTS / "viewer3d-mixed.png"))
    before = canvas_image(tab)
    tab.select_option("#colour", "plain")
    assert canvas_image(tab) != before
    tab.select_option("#colour", "kind")
    assert errors == []
    assert all(url.startswith("file://") for url in requests), requests


def test_clip_keeps_whole_cells_and_opens_polygons(page: tuple[Any, list[str], list[str]],
                                                   mesh: MixedMesh3) -> None:
    """Moving the clip keeps the cells whose vertices' mean is at most the position (the
    counts by kind match an exact count), opens faces (quads among them) and changes the
    picture; back at the end of the slider every cell is kept."""
    tab, errors, _ = page
    tab.select_option("#clip-axis", "z")
    whole = canvas_image(tab)
    assert int(_dataset(tab, "cells")) == mesh.cell_count
    _move_clip(tab, 500)
    position = Fraction(tab.evaluate("() => geomexactView3d.state.clipValue"))
    expected = [cell for cell in mesh.cell_list()
                if sum(Fraction(mesh.point(v).z) for v in cell.vertices)
                <= position * len(cell.vertices)]
    assert 0 < len(expected) < mesh.cell_count
    assert int(_dataset(tab, "cells")) == len(expected)
    assert json.loads(_dataset(tab, "keptKinds")) == _kinds(expected)
    assert "faces cut open" in tab.inner_text("#stats-table")
    assert canvas_image(tab) != whole
    sizes = tab.evaluate("() => geomexactView3d.frame.sizes")
    assert int(sizes.get("4", 0)) > 0
    tab.screenshot(path=str(ARTIFACTS / "viewer3d-mixed-clip.png"))
    tab.select_option("#clip-axis", "y")
    _move_clip(tab, 0)
    _move_clip(tab, 1000)
    assert int(_dataset(tab, "cells")) == mesh.cell_count
    tab.check("#all-tets")
    tab.evaluate("""() => { const s = document.getElementById('shrink');
        s.value = '0.3'; s.dispatchEvent(new Event('input')); }""")
    sizes = tab.evaluate("() => geomexactView3d.frame.sizes")
    assert int(sizes.get("5", 0)) >= 1 and int(sizes.get("4", 0)) > 0
    assert errors == []
