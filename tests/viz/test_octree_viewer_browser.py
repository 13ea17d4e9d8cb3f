"""The level-6 sphere-surface octree mesh (about 140,000 tetrahedra) end to end: ``geomexact
octree`` writes it as ``.vtu`` and as TetGen ``.ele``, both read back with the same
tetrahedron count, ``geomexact view`` makes the offline page of the ``.vtu``, and in
headless Chromium the page draws it, rotates it on a drag and opens it with the clip
slider, with no console error and no network request.  About 30 s."""

from __future__ import annotations

import io
import json
from contextlib import redirect_stdout
from pathlib import Path
from typing import Any

import pytest
from helpers.chromium import canvas_image, canvas_inked

from geomexact.cli import main
from geomexact.io import read
from geomexact.mesh3d.snapshot import Mesh3

pytestmark = pytest.mark.browser

ARTIFACTS = Path(__file__).resolve().parents[2] / "artifacts" / "browser"
SPHERE = ("octree", "--refine-sphere", "0.5", "0.5", "0.5", "0.3", "--surface", "--level",
          "6", "--no-progress", "--json")


def _run(*argv: str) -> Any:
    """``main(argv)``'s JSON report (module-scoped fixtures have no ``capsys``)."""
    out = io.StringIO()
    with redirect_stdout(out):
        assert main(list(argv)) == 0
    return json.loads(out.getvalue())


@pytest.fixture(scope="module")
def sphere_files(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """The command run twice (.vtu, .ele), then the viewer of the .vtu."""
    directory = tmp_path_factory.mktemp("octree6")
    reports = {name: _run(*SPHERE, "-o", str(directory / name))
               for name in ("m.vtu", "m.ele")}
    html = directory / "m.html"
    _run("view", str(directory / "m.vtu"), "-o", str(html), "--json")
    return {"directory": directory, "reports": reports, "html": html}


def test_both_files_read_back_with_every_tetrahedron(sphere_files: dict[str, Any]) -> None:
    vtu, ele = (sphere_files["reports"][name] for name in ("m.vtu", "m.ele"))
    assert vtu["digest"] == ele["digest"] and vtu["conforming"] and vtu["volume"] == "1"
    assert vtu["tetrahedra"] >= 100_000
    assert max(int(level) for level in vtu["levels"]) == 6
    for name in ("m.vtu", "m.ele"):
        mesh = read(sphere_files["directory"] / name)
        assert isinstance(mesh, Mesh3)
        assert mesh.tetrahedron_count == vtu["tetrahedra"]
        assert mesh.vertex_count == vtu["vertices"]
        if name == "m.ele":  # decimals only: TetGen's text holds the mesh exactly
            assert mesh.digest_text == ele["digest"]


def _stat(tab: Any, name: str) -> int:
    return int(tab.evaluate(
        f"() => document.getElementById('stats-table').dataset.{name}"))


def _row(tab: Any, label: str) -> int | None:
    value = tab.evaluate(f"""() => {{
        for (const tr of document.querySelectorAll('#stats-table tr'))
            if (tr.querySelector('th').textContent === '{label}')
                return tr.querySelector('td').textContent;
        return null; }}""")
    return None if value is None else int(value)


def _orange(tab: Any) -> int:
    """Pixels in the cut colour (240, 170, 110) times a shade."""
    count: int = tab.evaluate("""() => {
        const c = document.getElementById('view');
        const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
        let n = 0;
        for (let i = 0; i < d.length; i += 4)
            if (d[i] > d[i + 2] + 60 && d[i + 1] > d[i + 2] + 20) n++;
        return n; }""")
    return count


def test_the_viewer_draws_rotates_and_clips(browser: Any,
                                            sphere_files: dict[str, Any]) -> None:
    total = sphere_files["reports"]["m.vtu"]["tetrahedra"]
    errors: list[str] = []
    requests: list[str] = []
    context = browser.new_context(viewport={"width": 1000, "height": 700})
    context.route("**/*", lambda route: route.continue_()
                  if route.request.url.startswith("file://") else route.abort())
    tab = context.new_page()
    tab.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    tab.on("pageerror", lambda e: errors.append(str(e)))
    tab.on("request", lambda r: requests.append(r.url))
    try:
        tab.goto(sphere_files["html"].as_uri())
        tab.wait_for_selector("#stats-table tr", state="attached", timeout=60_000)
        assert _row(tab, "tetrahedra") == total
        assert _stat(tab, "tetrahedra") == total and _stat(tab, "faces") > 0
        assert canvas_inked(tab) > 20_000, "the mesh is drawn"
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        tab.screenshot(path=str(ARTIFACTS / "octree6-whole.png"))
        before = canvas_image(tab)
        box = tab.locator("#view").bounding_box()
        x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        tab.mouse.move(x, y)
        tab.mouse.down()
        tab.mouse.move(x + 120, y + 40, steps=3)
        tab.mouse.up()
        rotated = canvas_image(tab)
        assert rotated != before, "a drag rotates the view"
        assert _row(tab, "faces cut open") is None
        tab.select_option("#colour", "plain")
        tab.select_option("#clip-axis", "x")
        tab.evaluate("""() => { const s = document.getElementById('clip');
            s.value = '500'; s.dispatchEvent(new Event('input')); }""")
        kept = _stat(tab, "tetrahedra")
        assert 0 < kept < total
        cut = _row(tab, "faces cut open")
        assert cut is not None and cut > 1000
        assert _orange(tab) > 5000, "the cut faces are drawn in the cut colour"
        tab.screenshot(path=str(ARTIFACTS / "octree6-clip-half.png"))
        tab.evaluate("""() => { const s = document.getElementById('clip');
            s.value = '250'; s.dispatchEvent(new Event('input')); }""")
        assert 0 < _stat(tab, "tetrahedra") < kept
        assert errors == []
        assert all(url.startswith("file://") for url in requests), requests
    finally:
        context.close()
