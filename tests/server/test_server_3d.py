"""``geomexact serve`` shows tetrahedral meshes (issue 27, item 8): the 3D files it lists
(TetGen .node/.ele/.face, VTU of tetrahedra) open in the 3D viewer, and a trace recorded
on a tetrahedral mesh opens with it, step by step."""

from __future__ import annotations

import json
import re
import urllib.parse
from collections.abc import Iterator
from pathlib import Path

import pytest
from helpers.mesh3d_cases import cube_grid
from helpers.server_client import SQUARE_OFF, Log, alert, request, running

from geomexact import io
from geomexact.server import MeshServer, ServeOptions
from geomexact.viz.scene3d import PAYLOAD3_FORMAT


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from geomexact.io.trace_file import write_trace
    from geomexact.mesh3d.cuboid.partition import partition_cuboid

    root = tmp_path_factory.mktemp("served3d")
    cube = cube_grid(2, 2, 2)
    io.write(root / "cube.ele", cube, format="tetgen")
    io.write(root / "cube.vtu", cube)
    (root / "runs").mkdir()
    run = partition_cuboid(0b101101, improve=True)
    io.write(root / "runs" / "start.ele", run.start)
    write_trace(root / "runs" / "start.trace.jsonl", run.trace)
    (root / "square.off").write_text(SQUARE_OFF)
    return root


@pytest.fixture(scope="module")
def server(served: Path) -> Iterator[MeshServer]:
    log = Log()
    with running(ServeOptions(served, port=0), log) as server:
        yield server
    assert "Traceback" not in log.getvalue(), log.getvalue()


def payload(page: str) -> dict[str, object]:
    """The viewer page's JSON payload."""
    match = re.search(r'<script type="application/json" id="geomexact-data">(.*?)</script>',
                      page, re.S)
    assert match is not None, page[:300]
    data = json.loads(match.group(1))
    assert isinstance(data, dict)
    return data


def listed_links(server: MeshServer) -> list[str]:
    status, page = request(server, "GET", "/")
    assert status == 200
    return re.findall(r'href="(/view\?[^"]*)"', page)


def test_the_3d_files_are_listed(server: MeshServer) -> None:
    """TetGen's .ele (its .node and .face are part of it) and the VTU are listed."""
    links = listed_links(server)
    assert "/view?file=cube.ele" in links and "/view?file=cube.vtu" in links
    assert "/view?file=cube.node" not in links


@pytest.mark.parametrize("name", ["cube.ele", "cube.vtu"])
def test_every_listed_3d_file_opens_in_the_3d_viewer(server: MeshServer, name: str) -> None:
    """A listed tetrahedral mesh: 200 and the 3D viewer's page with its 48 tetrahedra
    (was 500 "cannot draw a Mesh3")."""
    status, page = request(server, "GET", f"/view?file={name}")
    assert status == 200, alert(page)
    data = payload(page)
    assert data["format"] == PAYLOAD3_FORMAT and data["title"] == name
    assert data["vertex_count"] == 27 and data["steps"] == 0


def test_each_listed_file_is_viewable(server: MeshServer) -> None:
    """Every link of the index answers 200 (2D, 3D and the 3D trace alike)."""
    for link in listed_links(server):
        status, page = request(server, "GET", link.replace("&amp;", "&"))
        assert status == 200, (link, alert(page))


def test_a_3d_trace_opens_with_its_input(server: MeshServer) -> None:
    """A trace recorded on a tetrahedral mesh: its input is found beside it by digest and
    the 3D page steps through it."""
    trace = urllib.parse.quote("runs/start.trace.jsonl")
    assert f"/view?trace={trace}" in listed_links(server)
    status, page = request(server, "GET", f"/view?trace={trace}")
    assert status == 200, alert(page)
    data = payload(page)
    assert data["format"] == PAYLOAD3_FORMAT
    assert isinstance(data["steps"], int) and data["steps"] > 0


def test_a_3d_trace_on_another_mesh_is_refused(server: MeshServer) -> None:
    """Naming a tetrahedral mesh that is not the trace's input: 404 naming the trace."""
    status, page = request(server, "GET",
                           "/view?file=cube.ele&trace=runs/start.trace.jsonl")
    assert status == 404, alert(page)
    assert "runs/start.trace.jsonl" in alert(page)
