"""``geomexact serve`` over HTTP (geomexact.server): listing, viewing, uploading,
and its limits (request size, run time, concurrent jobs, loopback names, paths)."""

from __future__ import annotations

import http.client
import json
import re
import shutil
import threading
import uuid
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from geomexact import io
from geomexact import server as serve
from geomexact.io.trace_file import write_trace
from geomexact.mesh2d.delaunay.triangulation import triangulate
from geomexact.mesh2d.pslg import PSLG
from geomexact.server import MeshServer, ServeOptions, make_server

SUPERIOR = Path(__file__).resolve().parents[2] / "geomexact" / "data" / "superior.poly"
SQUARE_OFF = "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n"


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A directory with Superior (PSLG, its triangulation as Triangle files and its
    trace), a square OFF in a subdirectory, a malformed OFF and a file of no format."""
    root = tmp_path_factory.mktemp("served")
    shutil.copy(SUPERIOR, root / "superior.poly")
    pslg = io.read(SUPERIOR)
    assert isinstance(pslg, PSLG)
    run = triangulate(pslg)
    io.write(root / "superior.1.ele", run.mesh, exact=True)
    write_trace(root / "superior.1.trace.jsonl", run.trace)
    (root / "meshes").mkdir()
    (root / "meshes" / "square.off").write_text(SQUARE_OFF)
    (root / "bad.off").write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n")
    (root / "notes.md").write_text("not a mesh\n")
    (root / ".hidden.off").write_text(SQUARE_OFF)
    return root


def start(options: ServeOptions) -> Iterator[MeshServer]:
    server = make_server(options)
    thread = threading.Thread(target=server.serve_forever, kwargs={"poll_interval": 0.05},
                              daemon=True)
    thread.start()
    try:
        yield server
    finally:
        server.shutdown()
        server.server_close()
        thread.join(5)


@pytest.fixture(scope="module")
def server(served: Path) -> Iterator[MeshServer]:
    yield from start(ServeOptions(served, port=0, time_limit=60, jobs=2))


def request(server: MeshServer, method: str, path: str, body: bytes | None = None,
            headers: dict[str, str] | None = None) -> tuple[int, str]:
    host, port = server.server_address[:2]
    connection = http.client.HTTPConnection(str(host), int(port), timeout=90)
    try:
        connection.request(method, path, body=body, headers=headers or {})
        response = connection.getresponse()
        return response.status, response.read().decode("utf-8")
    finally:
        connection.close()


def multipart(files: list[tuple[str, bytes]], fields: dict[str, str]) -> tuple[bytes, str]:
    boundary = uuid.uuid4().hex
    parts = []
    for name, data in files:
        parts.append(f'--{boundary}\r\nContent-Disposition: form-data; name="files"; '
                     f'filename="{name}"\r\nContent-Type: application/octet-stream\r\n\r\n'
                     .encode() + data + b"\r\n")
    for key, value in fields.items():
        parts.append(f'--{boundary}\r\nContent-Disposition: form-data; name="{key}"\r\n\r\n'
                     f"{value}\r\n".encode())
    parts.append(f"--{boundary}--\r\n".encode())
    return b"".join(parts), f"multipart/form-data; boundary={boundary}"


def upload(server: MeshServer, files: list[tuple[str, bytes]], **fields: str
           ) -> tuple[int, str]:
    body, content_type = multipart(files, fields)
    return request(server, "POST", "/upload", body, {"Content-Type": content_type})


def payload(page: str) -> dict[str, Any]:
    match = re.search(r'id="geomexact-data">(.*?)</script>', page, re.S)
    assert match is not None, page[:500]
    data: dict[str, Any] = json.loads(match.group(1))
    return data


def alert(page: str) -> str:
    match = re.search(r'role="alert">(.*?)</p>', page, re.S)
    assert match is not None, page[:500]
    return match.group(1)


# ---------------------------------------------------------------------------------------
# listing and viewing
# ---------------------------------------------------------------------------------------
def test_index_lists_mesh_files_and_traces(server: MeshServer) -> None:
    """The index links every mesh, PSLG and trace file (subdirectories included); a .node
    or .poly beside an .ele of the same stem, hidden files and other files are not
    listed; the upload form is there."""
    status, page = request(server, "GET", "/")
    assert status == 200
    links = re.findall(r'href="(/view\?[^"]+)"', page)
    assert links == [
        "/view?file=bad.off",
        "/view?file=meshes/square.off",
        "/view?file=superior.1.ele",
        "/view?file=superior.poly",
        "/view?trace=superior.1.trace.jsonl",
    ]
    assert 'action="/upload"' in page and 'enctype="multipart/form-data"' in page
    assert "notes.md" not in page and "hidden" not in page


def test_view_a_file(server: MeshServer) -> None:
    """/view?file= answers the viewer page of that file."""
    status, page = request(server, "GET", "/view?file=meshes/square.off")
    assert status == 200
    data = payload(page)
    assert data["scene"]["summary"]["triangles"] == 2
    assert 'href="/"' in page


def test_view_a_trace_finds_its_input_by_digest(server: MeshServer) -> None:
    """/view?trace= finds the file beside it whose start digest is the trace's input
    (superior.poly, not superior.1.ele) and shows the history."""
    status, page = request(server, "GET", "/view?trace=superior.1.trace.jsonl")
    assert status == 200
    data = payload(page)
    assert data["history"]["steps"] == 2517
    assert data["source"] == {"file": "superior.poly", "trace": "superior.1.trace.jsonl"}


def test_trace_with_the_wrong_file_is_refused(server: MeshServer) -> None:
    """A trace paired explicitly with a mesh it was not recorded on: 404 naming the
    digest."""
    status, page = request(server, "GET",
                           "/view?file=meshes/square.off&trace=superior.1.trace.jsonl")
    assert status == 404
    assert "input digest" in alert(page)


@pytest.mark.parametrize("path", ["/view?file=../etc/passwd", "/view?file=/etc/passwd",
                                  "/view?file=meshes/../../x.off", "/view?file=missing.off",
                                  "/view?file=meshes", "/nothing-here"])
def test_paths_outside_the_directory_are_not_served(server: MeshServer, path: str) -> None:
    """Traversal, absolute paths, directories and missing files: 404."""
    status, _ = request(server, "GET", path)
    assert status == 404


def test_bad_file_gets_a_clear_error(server: MeshServer) -> None:
    """A malformed served file: 400 and the reader's message with the file and line."""
    status, page = request(server, "GET", "/view?file=bad.off")
    assert status == 400
    assert alert(page).startswith("bad.off:4: ")
    assert str(server.options.directory.resolve()) not in alert(page)


def test_empty_viewer(server: MeshServer) -> None:
    """/viewer is the viewer without data (it opens local files)."""
    status, page = request(server, "GET", "/viewer")
    assert status == 200 and 'id="file-input"' in page
    assert 'id="geomexact-data"></script>' in page


# ---------------------------------------------------------------------------------------
# uploads
# ---------------------------------------------------------------------------------------
def test_upload_triangulates_a_pslg(server: MeshServer) -> None:
    """Uploading a .poly with action triangulate: the viewer of its constrained Delaunay
    triangulation with the whole trace, an exact download and a link back."""
    status, page = upload(server, [("superior.poly", SUPERIOR.read_bytes())],
                          action="triangulate")
    assert status == 200, page[:300]
    data = payload(page)
    assert data["history"]["steps"] == 2517
    assert data["scene"]["summary"]["triangles"] == 528
    assert data["download"]["name"] == "superior.triangulate.pslg"
    assert data["download"]["text"].count("\nt ") == 528


def test_upload_a_triangle_pair(server: MeshServer, served: Path) -> None:
    """An .ele uploaded with its .node is read as one mesh (Lawson flips: no change)."""
    files = [(name, (served / name).read_bytes()) for name in ("superior.1.node",
                                                               "superior.1.ele")]
    status, page = upload(server, files, action="triangulate")
    assert status == 200, alert(page)
    assert payload(page)["scene"]["summary"]["triangles"] == 528


@pytest.mark.skipif("refine" not in serve.available_actions(),
                    reason="geomexact.mesh2d.refinement.api is not installed")
def test_upload_refines(server: MeshServer) -> None:
    """Action refine with a maximum area: more triangles than the triangulation, every
    one at most that area, with the refinement's trace."""
    status, page = upload(server, [("superior.poly", SUPERIOR.read_bytes())],
                          action="refine", criterion="max_area", value="0.001",
                          method="centroid", max_steps="100000")
    assert status == 200, alert(page)
    data = payload(page)
    summary = data["scene"]["summary"]
    assert summary["triangles"] > 528 and summary["max_area"] <= 0.001
    assert data["history"]["steps"] > 0


def test_upload_of_a_bad_file(server: MeshServer) -> None:
    """A malformed upload: 400, the problem named by file name and line (not the server's
    temporary path)."""
    status, page = upload(server, [("broken.off", b"OFF\n3 1 0\n0 0 0\n1 0 0\n")],
                          action="triangulate")
    assert status == 400
    message = alert(page)
    assert message.startswith("broken.off:"), message
    assert "/tmp" not in message and "geomexact-upload" not in message


@pytest.mark.parametrize(("fields", "expected"), [
    ({"action": "frobnicate"}, "unknown action"),
    ({"action": "triangulate"}, "choose a mesh file"),
])
def test_upload_form_problems(server: MeshServer, fields: dict[str, str], expected: str
                              ) -> None:
    """An unknown action or no file: 400 with the reason."""
    files = [] if expected == "choose a mesh file" else [("a.off", SQUARE_OFF.encode())]
    status, page = upload(server, files, **fields)
    assert status == 400 and expected in alert(page)


def test_upload_names_are_reduced_to_file_names() -> None:
    """Directories and odd characters never reach the file system."""
    assert serve.safe_name("../../etc/passwd") == "passwd"
    assert serve.safe_name("C:\\x\\m e$h.off") == "m_e_h.off"
    assert serve.safe_name("..") == "upload"


def test_multipart_parsing() -> None:
    """Files and fields of a multipart body, an empty file input ignored."""
    body, content_type = multipart([("a.off", b"OFF\n"), ("", b"")], {"action": "refine"})
    files, fields = serve.parse_multipart(content_type, body)
    assert files == [("a.off", b"OFF\n")]
    assert fields == {"action": "refine"}


# ---------------------------------------------------------------------------------------
# limits and checks
# ---------------------------------------------------------------------------------------
@pytest.fixture()
def strict_server(served: Path) -> Iterator[MeshServer]:
    yield from start(ServeOptions(served, port=0, max_upload_bytes=2000, time_limit=1.0,
                                  jobs=1, view_jobs=1))


def test_upload_size_is_bounded(strict_server: MeshServer) -> None:
    """A body larger than max_upload_bytes: 413, and nothing is run."""
    status, page = upload(strict_server, [("superior.poly", SUPERIOR.read_bytes())],
                          action="triangulate")
    assert status == 413
    assert "at most 2,000" in alert(page)


def test_run_time_is_bounded(strict_server: MeshServer) -> None:
    """A job running past the time limit is stopped: 503 naming the limit."""
    heavy = (b"v 0 0\nv 1 0\nv 1 1\nv 0 1\ns 0 1\ns 1 2\ns 2 3\ns 3 0\n")
    action = "refine" if "refine" in serve.available_actions() else None
    if action is None:
        pytest.skip("needs geomexact.mesh2d.refinement.api for a long job")
    status, page = upload(strict_server, [("square.pslg", heavy)], action="refine",
                          criterion="max_area", value="1e-9", method="centroid",
                          max_steps="5000000")
    assert status == 503
    assert "time limit of 1 s" in alert(page)


def test_busy_server_says_so(strict_server: MeshServer) -> None:
    """With every slot of a pool taken, a request that needs a job of that pool gets 503
    busy: viewing for the viewing slots, uploads for the upload slots."""
    assert strict_server.view_slots.try_acquire()
    try:
        status, page = request(strict_server, "GET", "/view?file=meshes/square.off")
    finally:
        strict_server.view_slots.release()
    assert status == 503 and "busy" in alert(page)
    assert strict_server.upload_slots.try_acquire()
    try:
        status, page = upload(strict_server, [("a.off", SQUARE_OFF.encode())],
                              action="triangulate")
    finally:
        strict_server.upload_slots.release()
    assert status == 503 and "busy" in alert(page)


def test_job_errors_are_reported() -> None:
    """A job that raises is reported as a failed job, never hangs the server."""
    with pytest.raises(serve.JobFailed) as caught:
        serve.run_bounded(serve.view_job, (Path("/nonexistent"), None, None), 30)
    assert caught.value.status == 400


def test_only_loopback_names_are_answered(server: MeshServer) -> None:
    """On loopback, a request for another Host (DNS rebinding) is refused."""
    status, _ = request(server, "GET", "/", headers={"Host": "evil.example:8765"})
    assert status == 403
    for host in ("localhost:1", "127.0.0.1", "[::1]:8765"):
        status, _ = request(server, "GET", "/", headers={"Host": host})
        assert status == 200, host


def test_uploads_from_other_sites_are_refused(server: MeshServer) -> None:
    """A POST whose Origin is another site: 403."""
    body, content_type = multipart([("a.off", SQUARE_OFF.encode())], {"action": "triangulate"})
    status, _ = request(server, "POST", "/upload", body,
                        {"Content-Type": content_type, "Origin": "https://evil.example"})
    assert status == 403


def test_pages_forbid_scripts_and_outside_resources(server: MeshServer) -> None:
    """The index page has a CSP without scripts and with form-action 'self'."""
    _, page = request(server, "GET", "/")
    assert "<script" not in page
    assert "default-src 'none'" in page and "form-action 'self'" in page


def test_missing_directory_is_refused(tmp_path: Path) -> None:
    """Serving a directory that does not exist: NotADirectoryError before binding."""
    with pytest.raises(NotADirectoryError):
        make_server(ServeOptions(tmp_path / "missing", port=0))
