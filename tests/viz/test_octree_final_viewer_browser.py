"""Each octree final, written by ``geomexact octree`` and drawn from the file by
``geomexact view``, in headless Chromium (issue 23): the page draws without errors,
reports the cells (by kind) that the octree command reported, and the clip plane opens
it."""

from __future__ import annotations

import contextlib
import io
import json
from collections.abc import Iterator
from typing import Any

import pytest
from helpers.chromium import canvas_image, canvas_inked, open_offline_page

from geomexact.cli import main

pytestmark = pytest.mark.browser

SHELL = ["--level", "4", "--refine-sphere", "1/2", "1/2", "1/2", "3/10", "--surface"]


def _command(*argv: str) -> str:
    """What ``geomexact ARGV`` prints (it must succeed)."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(list(argv)) == 0
    return out.getvalue()


@pytest.fixture(scope="module", params=["patterns", "mixed", "polyhedral"])
def drawn(request: pytest.FixtureRequest, browser: Any,
          tmp_path_factory: pytest.TempPathFactory
          ) -> Iterator[tuple[Any, list[str], dict[str, Any]]]:
    folder = tmp_path_factory.mktemp(request.param)
    mesh, page = folder / "m.vtu", folder / "m.html"
    report = json.loads(_command("octree", *SHELL, "--final", request.param, "-o", str(mesh),
                                 "--json"))
    _command("view", str(mesh), "-o", str(page))
    for tab, errors, _ in open_offline_page(browser, page):
        yield tab, errors, report


def test_the_page_draws_the_octree_final(drawn: tuple[Any, list[str], dict[str, Any]]
                                         ) -> None:
    tab, errors, report = drawn
    assert canvas_inked(tab) > 20_000
    stats = tab.evaluate("() => ({...document.getElementById('stats-table').dataset})")
    if report["final"] == "patterns":
        assert f"{report['tetrahedra']:,}" in tab.inner_text("#stats-table") or str(
            report["tetrahedra"]) in tab.inner_text("#stats-table")
    else:
        assert json.loads(stats["kinds"]) == report["cells_by_kind"]
        assert int(stats["cells"]) == report["cells"]
    whole = canvas_image(tab)
    tab.select_option("#clip-axis", "x")
    tab.evaluate("""() => { const s = document.getElementById('clip');
        s.value = '500'; s.dispatchEvent(new Event('input')); }""")
    assert canvas_image(tab) != whole
    assert errors == []
