"""The self-contained HTML viewer page (geomexact.viz.viewer): everything inline, nothing
fetched, a payload that decodes back to the scene and history, byte-identical output."""

from __future__ import annotations

import base64
import html.parser
import json
import re
import shutil
import subprocess
from array import array
from pathlib import Path
from typing import Any

import pytest

from geomexact import io
from geomexact.errors import OverwriteError, TraceError
from geomexact.kernel.points import point2
from geomexact.mesh2d.delaunay.triangulation import triangulate
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh2d.transient import mesh_from_triangles
from geomexact.viz import viewer
from geomexact.viz.scene import INDEX_TYPE, history_of, scene_of
from geomexact.viz.viewer import (
    Download,
    empty_viewer_html,
    render_page,
    viewer_html,
    write_viewer,
)

SUPERIOR = Path(__file__).resolve().parents[2] / "geomexact" / "data" / "superior.poly"
VIZ = Path(viewer.__file__).resolve().parent


@pytest.fixture(scope="module")
def superior() -> PSLG:
    pslg = io.read(SUPERIOR)
    assert isinstance(pslg, PSLG)
    return pslg


def square() -> Mesh2:
    return mesh_from_triangles([("0", "0"), ("1", "0"), ("1", "1"), ("0", "1")],
                               [(0, 1, 2), (0, 2, 3)], [(0, 1, 1)])


def payload_of(page: str) -> dict[str, Any]:
    match = re.search(
        r'<script type="application/json" id="geomexact-data">(.*?)</script>', page, re.S
    )
    assert match is not None
    loaded: dict[str, Any] = json.loads(match.group(1))
    return loaded


def decode(text: str, typecode: str) -> list[Any]:
    values = array(typecode)
    values.frombytes(base64.b64decode(text))
    return list(values)


class _Tags(html.parser.HTMLParser):
    """Every tag with its attributes."""

    def __init__(self) -> None:
        super().__init__()
        self.tags: list[tuple[str, dict[str, str | None]]] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        self.tags.append((tag, dict(attrs)))


def tags_of(page: str) -> list[tuple[str, dict[str, str | None]]]:
    parser = _Tags()
    parser.feed(page)
    return parser.tags


def test_page_is_self_contained(superior: PSLG) -> None:
    """No element loads anything: no src, no stylesheet link, the only link is the inline
    data: icon; a CSP forbids every fetch and connection; no http(s) URL anywhere."""
    page = viewer_html(superior, trace=triangulate(superior).trace, source="superior.poly")
    tags = tags_of(page)
    for tag, attributes in tags:
        assert "src" not in attributes, tag
        if tag == "link":
            assert attributes.get("href") == "data:,", attributes
    csp = [a["content"] for t, a in tags if t == "meta" and a.get("http-equiv")]
    assert csp and "default-src 'none'" in (csp[0] or "")
    assert "connect-src" not in (csp[0] or "")  # falls back to default-src 'none'
    assert not re.search(r"https?://", page)
    scripts = [a for t, a in tags if t == "script"]
    assert len(scripts) == 2  # the JSON payload and the inline viewer


def test_payload_decodes_to_the_scene() -> None:
    """The base64 typed arrays of the payload are the scene's arrays."""
    mesh = square()
    data = payload_of(viewer_html(mesh, source="square.off"))
    assert data["format"] == "geomexact-view" and data["version"] == 1
    scene = data["scene"]
    assert decode(scene["xy"], "d") == [0, 0, 1, 0, 1, 1, 0, 1]
    assert decode(scene["triangles"], INDEX_TYPE) == [0, 1, 2, 0, 2, 3]
    assert decode(scene["segments"], INDEX_TYPE) == [0, 1]
    assert scene["exact"] == ["0 0", "1 0", "1 1", "0 1"]
    assert scene["summary"]["digest"] == mesh.digest_text
    assert data["history"] is None
    assert data["source"] == {"file": "square.off", "trace": None}


def test_payload_history_matches_history_of(superior: PSLG) -> None:
    """With a trace, the payload carries the history (offsets of length steps+1) and no
    duplicate triangle table; the step labels are those of the trace."""
    run = triangulate(superior)
    data = payload_of(viewer_html(superior, trace=run.trace))
    history = history_of(run.start, run.trace)
    carried = data["history"]
    assert carried["steps"] == len(run.trace)
    assert decode(carried["added_offsets"], INDEX_TYPE) == list(history.triangles.added_offsets)
    assert decode(carried["removed"], INDEX_TYPE) == list(history.triangles.removed)
    assert decode(carried["cells"], INDEX_TYPE) == list(history.triangles.cells)
    assert decode(carried["vertex_counts"], INDEX_TYPE)[-1] == 518
    assert len(decode(carried["added_offsets"], INDEX_TYPE)) == len(run.trace) + 1
    assert carried["labels"] == list(history.labels)
    assert data["scene"]["triangles"] == "" and data["scene"]["segments"] == ""
    assert data["scene"]["summary"]["triangles"] == 528
    assert data["options"] == {"fill": "none", "step": None}


def test_output_is_byte_identical(superior: PSLG) -> None:
    """The same input gives the same bytes (sorted keys, sorted triangles)."""
    run = triangulate(superior)
    first = viewer_html(superior, trace=run.trace, title="x")
    second = viewer_html(superior, trace=run.trace, title="x")
    assert first == second


def test_payload_cannot_close_its_script_element() -> None:
    """A title, a note and a download text holding '</script>' stay inside the payload:
    '<' is written as \\u003c and the JSON still reads back."""
    hostile = "</script><script>alert(1)</script><!--"
    page = viewer_html(square(), title=hostile, notes=[hostile],
                       download=Download("x.pslg", hostile))
    assert page.count("</script>") == 2
    data = payload_of(page)
    assert data["title"] == hostile and data["notes"] == [hostile]
    assert data["download"] == {"name": "x.pslg", "text": hostile}
    assert "<title>&lt;/script&gt;" in page


def test_inline_assets_cannot_end_their_element() -> None:
    """The bundled JS and CSS contain nothing that would close their inline element; a
    file that did is refused."""
    for name in ("viewer.js", "viewer3d.js", "step_controls.js", "viewer.css"):
        text = (VIZ / name).read_text(encoding="utf-8")
        assert viewer._check_inline(name, text) == text
    with pytest.raises(ValueError, match="</script"):
        viewer._check_inline("viewer.js", "let a = '</SCRIPT>';")


def test_polygon_mesh_and_pslg_pages() -> None:
    """Polygon meshes and PSLGs have pages too, with their own kind."""
    points = [point2(*p) for p in [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]]
    polygons = payload_of(viewer_html(PolygonMesh(points, [(0, 1, 2, 3, 4, 5)])))
    assert polygons["scene"]["kind"] == "polygons"
    assert decode(polygons["scene"]["polygon_offsets"], INDEX_TYPE) == [0, 6]
    assert decode(polygons["scene"]["nonconvex"], INDEX_TYPE) == [0]
    pslg = payload_of(viewer_html(PSLG(points, [(0, 1, 1)])))
    assert pslg["scene"]["kind"] == "pslg"


def test_options_are_checked(superior: PSLG) -> None:
    """An unknown fill mode, a step outside the trace, a trace on another mesh: errors."""
    run = triangulate(superior)
    with pytest.raises(ValueError, match="fill"):
        viewer_html(square(), fill="rainbow")
    with pytest.raises(ValueError, match="outside"):
        viewer_html(superior, trace=run.trace, step=len(run.trace) + 1)
    with pytest.raises(TraceError):
        viewer_html(square(), trace=run.trace)
    data = payload_of(viewer_html(superior, trace=run.trace, step=10, fill="min_angle"))
    assert data["options"] == {"fill": "min_angle", "step": 10}


def test_write_viewer_refuses_to_overwrite(tmp_path: Path) -> None:
    """write_viewer writes atomically and refuses to replace a file unless overwrite."""
    target = tmp_path / "view.html"
    assert write_viewer(target, square()) == target
    assert target.read_text(encoding="utf-8").startswith("<!DOCTYPE html>")
    with pytest.raises(OverwriteError):
        write_viewer(target, square())
    write_viewer(target, square(), overwrite=True, title="again")
    assert "<title>again</title>" in target.read_text(encoding="utf-8")


def test_empty_viewer_has_no_payload() -> None:
    """The empty viewer (serve's /viewer) has the page and controls, no data."""
    page = empty_viewer_html(links=(("files", "/"),))
    assert 'id="geomexact-data"></script>' in page
    assert 'href="/"' in page and 'id="file-input"' in page
    assert render_page(None, title="t").count("<script") == 2


def test_exact_budget_zero_drops_exact_text() -> None:
    """exact_budget=0 embeds no exact coordinates."""
    assert payload_of(viewer_html(square(), exact_budget=0))["scene"]["exact"] is None


@pytest.mark.skipif(shutil.which("node") is None, reason="node is not installed")
@pytest.mark.parametrize("name", ["viewer.js", "viewer3d.js", "step_controls.js"])
def test_viewer_script_parses(name: str) -> None:
    """The viewers' JavaScript is syntactically valid (node --check)."""
    result = subprocess.run(["node", "--check", str(VIZ / name)], capture_output=True,
                            text=True, check=False)
    assert result.returncode == 0, result.stderr


def test_both_pages_share_the_step_controls(superior: PSLG) -> None:
    """The 2D and the 3D page each hold the shared trace panel (go to step, op filter) and
    its script once, and no placeholder is left."""
    from geomexact.mesh3d.cuboid.partition import partition_cuboid
    from geomexact.viz.scene3d import viewer_html_3d

    run = partition_cuboid(0b101101, improve=True)
    pages = [viewer_html(superior, trace=triangulate(superior).trace),
             viewer_html_3d(run.start, run.trace)]
    script = (VIZ / "step_controls.js").read_text(encoding="utf-8")
    for page in pages:
        assert "{{" not in page.split('id="geomexact-data"')[0]
        for marker in ('id="step-go"', 'id="op-filter"', 'id="step-message"',
                       'id="next"', 'id="play"'):
            assert page.count(marker) == 1, marker
        assert page.count(script) == 1


def test_scene_summary_is_the_info_summary() -> None:
    """The exact statistics shown in the page are those of geomexact info."""
    from geomexact.mesh2d.summary import mesh_summary

    mesh = square()
    assert payload_of(viewer_html(mesh))["scene"]["summary"] == mesh_summary(mesh)
    assert scene_of(mesh, summary=False).summary == {}
