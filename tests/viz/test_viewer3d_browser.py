"""The 3D viewer page in headless Chromium (Debian's ``chromium`` via Playwright): it
draws, dragging rotates it, the step slider changes the tetrahedra shown, and nothing is
logged as an error or requested from the network."""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from helpers.chromium import canvas_image, canvas_inked, open_offline_page

from geomexact.mesh3d.cuboid.partition import partition_cuboid
from geomexact.trace.playback import replay
from geomexact.viz.scene3d import clip_plane, viewer_html_3d

pytestmark = pytest.mark.browser

ARTIFACTS = Path(__file__).resolve().parents[2] / "artifacts" / "browser"


@pytest.fixture(scope="module")
def page(browser: Any, tmp_path_factory: pytest.TempPathFactory
         ) -> Iterator[tuple[Any, list[str], list[str]]]:
    run = partition_cuboid(0b101101, improve=True)
    path: Path = tmp_path_factory.mktemp("view3d") / "cuboid.html"
    path.write_text(viewer_html_3d(run.start, run.trace, title="cuboid"), encoding="utf-8")
    yield from open_offline_page(browser, path)


@pytest.fixture(scope="module")
def octree_page(browser: Any, tmp_path_factory: pytest.TempPathFactory
                ) -> Iterator[tuple[Any, list[str], list[str]]]:
    """Pattern 262143 (every Steiner point), improved, opened with the clip at x = 1/2."""
    run = partition_cuboid(262143, improve=True)
    path: Path = tmp_path_factory.mktemp("view3d") / "full.html"
    path.write_text(viewer_html_3d(run.mesh, title="full", colour="plain",
                                   clip=clip_plane("x", "1/2")), encoding="utf-8")
    yield from open_offline_page(browser, path)


def _artifact(name: str) -> Path:
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    return ARTIFACTS / name


def _tetrahedra(tab: Any) -> int:
    return int(tab.evaluate(
        "() => document.getElementById('stats-table').dataset.tetrahedra"))


def test_draws_rotates_and_steps(page: tuple[Any, list[str], list[str]]) -> None:
    tab, errors, requests = page
    filled = tab.evaluate("""() => {
        const s = document.getElementById('stage').getBoundingClientRect();
        const c = document.getElementById('view').getBoundingClientRect();
        return c.width >= s.width - 1 && c.height >= s.height - 1; }""")
    assert filled, "the canvas fills the stage"
    assert canvas_inked(tab) > 20_000
    tab.screenshot(path=str(_artifact("viewer3d-cuboid-last.png")))
    before = canvas_image(tab)
    box = tab.locator("#view").bounding_box()
    x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
    tab.mouse.move(x, y)
    tab.mouse.down()
    tab.mouse.move(x + 120, y + 40, steps=5)
    tab.mouse.up()
    assert canvas_image(tab) != before
    last = _tetrahedra(tab)
    tab.evaluate("""() => { const s = document.getElementById('step');
        s.value = '0'; s.dispatchEvent(new Event('input')); }""")
    first = _tetrahedra(tab)
    assert first != last and first > 0
    assert canvas_inked(tab) > 1000
    zoomed = canvas_image(tab)
    tab.mouse.move(x, y)
    tab.mouse.wheel(0, -300)
    assert canvas_image(tab) != zoomed
    tab.evaluate("""() => { const s = document.getElementById('shrink');
        s.value = '0.5'; s.dispatchEvent(new Event('input')); }""")
    assert canvas_inked(tab) > 100
    by_quality = canvas_image(tab)
    tab.select_option("#colour", "step")
    assert canvas_image(tab) != by_quality
    legend = tab.inner_text("#legend")
    assert "split_tetra" in legend and "flip23" in legend
    tab.check("#all-tets")
    assert _tetrahedra(tab) == first
    tab.screenshot(path=str(_artifact("viewer3d-cuboid-first.png")))
    assert errors == []
    assert all(url.startswith("file://") for url in requests), requests


def _stat(tab: Any, name: str) -> int:
    return int(tab.evaluate(
        f"() => document.getElementById('stats-table').dataset.{name}"))


def _move_clip(tab: Any, value: int) -> None:
    tab.evaluate(f"""() => {{ const s = document.getElementById('clip');
        s.value = '{value}'; s.dispatchEvent(new Event('input')); }}""")


def test_clip_plane_opens_the_mesh(octree_page: tuple[Any, list[str], list[str]]) -> None:
    """The page starts with the clip of the payload; moving the slider changes the kept
    tetrahedra, the faces drawn and the picture; cut faces are drawn in the cut colour;
    the clip's "none" shows every tetrahedron again."""
    tab, errors, requests = octree_page
    assert tab.input_value("#clip-axis") == "x"
    assert "1/2" in tab.inner_text("#clip-value") or "0.5" in tab.inner_text("#clip-value")
    run = partition_cuboid(262143, improve=True)
    total = run.mesh.tetrahedron_count
    half = _tetrahedra(tab)
    assert 0 < half < total
    assert "faces cut open" in tab.inner_text("#stats-table")
    tab.screenshot(path=str(_artifact("viewer3d-clip-half.png")))
    half_image = canvas_image(tab)
    # the cut colour (240, 170, 110) times a shade: orange pixels are on the canvas
    orange = tab.evaluate("""() => {
        const c = document.getElementById('view');
        const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
        let n = 0;
        for (let i = 0; i < d.length; i += 4)
            if (d[i] > d[i + 2] + 60 && d[i + 1] > d[i + 2] + 20) n++;
        return n; }""")
    assert orange > 500
    _move_clip(tab, 200)
    quarter = _tetrahedra(tab)
    assert 0 < quarter < half
    assert canvas_image(tab) != half_image
    _move_clip(tab, 1000)
    assert _tetrahedra(tab) == total
    _move_clip(tab, 0)
    assert _tetrahedra(tab) < quarter
    tab.select_option("#clip-axis", "")
    assert _tetrahedra(tab) == total
    assert tab.locator("#clip").is_disabled()
    tab.select_option("#clip-axis", "z")
    _move_clip(tab, 500)
    assert 0 < _tetrahedra(tab) < total
    assert _stat(tab, "faces") > 0
    timings = tab.evaluate("() => geomexactView3d.timings")
    assert timings["draw"] >= 0 and timings["visible"] >= 0
    assert errors == []
    assert all(url.startswith("file://") for url in requests), requests


def _step(tab: Any) -> int:
    step: int = tab.evaluate("() => geomexactView3d.state.step")
    return step


def test_go_to_step_and_op_filter(page: tuple[Any, list[str], list[str]]) -> None:
    """Typing a step number shows that step (its number, label and tetrahedra, as
    geomexact replays them; a new drawing); out-of-range and non-numeric entries get a
    message; with an op chosen, next / previous / the slider's arrow keys visit only its
    steps, and the filter lists every op with its count."""
    tab, errors, requests = page
    run = partition_cuboid(0b101101, improve=True)
    steps = run.trace.steps
    tab.fill("#step-go", str(len(steps)))
    tab.press("#step-go", "Enter")
    at_end = canvas_image(tab)
    tab.fill("#step-go", "3")
    tab.press("#step-go", "Enter")
    assert _step(tab) == 3
    assert tab.inner_text("#step-number") == f"step 3 of {len(steps)}"
    assert tab.inner_text("#step-label") == str(steps[2])
    assert tab.locator("#step").input_value() == "3"
    assert _tetrahedra(tab) == replay(run.start, run.trace, until=3).tetrahedron_count
    assert canvas_image(tab) != at_end
    tab.fill("#step-go", "40")
    tab.click("#step-go-button")
    assert _step(tab) == len(steps)
    assert f"40 is outside 0..{len(steps)}" in tab.inner_text("#step-message")
    tab.fill("#step-go", "three")
    tab.press("#step-go", "Enter")
    assert _step(tab) == len(steps)
    assert "not a step number" in tab.inner_text("#step-message")
    counts = Counter(step.op for step in steps)
    options = tab.locator("#op-filter option").all_inner_texts()
    assert options == [f"all ({len(steps)})", *(f"{op} ({n})" for op, n in sorted(counts.items()))]
    flips = [k for k, step in enumerate(steps, 1) if step.op == "flip23"]
    assert 0 < len(flips) < len(steps)
    tab.select_option("#op-filter", "flip23")
    tab.click("#first")
    for expected in flips:
        tab.click("#next")
        assert _step(tab) == expected
        assert tab.inner_text("#step-label").startswith("flip23(")
    tab.click("#next")
    assert _step(tab) == flips[-1]
    assert f"no flip23 step after step {flips[-1]}" in tab.inner_text("#step-message")
    tab.focus("#step")
    tab.keyboard.press("ArrowLeft")
    assert _step(tab) == flips[-2]
    tab.keyboard.press("ArrowRight")
    assert _step(tab) == flips[-1]
    tab.select_option("#op-filter", "")
    tab.keyboard.press("ArrowLeft")
    assert _step(tab) == flips[-1] - 1
    tab.screenshot(path=str(_artifact("viewer3d-op-filter.png")))
    assert errors == []
    assert all(url.startswith("file://") for url in requests), requests
