"""``geomexact serve`` reads nothing outside DIR and shows no file's text (issue 11, part
4): symlinks out of DIR — the file itself or a companion a reader opens beside it — are
neither listed nor read; error pages name file, line and problem, never quote the file."""

from __future__ import annotations

import html
import os
import re
import tempfile
import urllib.parse
from collections.abc import Iterator
from pathlib import Path, PurePosixPath

import pytest
from helpers.mesh3d_cases import cube_grid
from helpers.server_client import SQUARE_OFF, alert, request, running

from geomexact import io
from geomexact.io.trace_file import write_trace
from geomexact.mesh2d.delaunay.triangulation import triangulate
from geomexact.mesh2d.pslg import PSLG
from geomexact.server import MeshServer, ServeOptions
from geomexact.server.read_failures import (
    NOT_SHOWN,
    failure_message,
    offending_line,
    without_file_text,
)
from geomexact.server.served_files import companion_names, relative_name

SECRET = "TOPSECRET-7f3a"
SUPERIOR = Path(__file__).resolve().parents[2] / "geomexact" / "data" / "superior.poly"


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """DIR beside an ``outside`` folder of secrets, with links out of DIR of every kind:
    a mesh whose ``.node`` / ``.neigh`` / ``.poly`` companion points out, a ``.poly`` with
    vertex count 0 whose ``.node`` points out, a file and a folder linked out, a dangling
    link out; links that stay inside DIR; non-mesh files with a mesh extension."""
    base = tmp_path_factory.mktemp("confined")
    root, outside = base / "served", base / "outside"
    root.mkdir()
    outside.mkdir()
    pslg = io.read(SUPERIOR)
    assert isinstance(pslg, PSLG)
    run = triangulate(pslg)
    (outside / "secret.node").write_text(f"{SECRET} x y\n")
    (outside / "secret.neigh").write_text(f"{SECRET}\n")
    (outside / "secret.poly").write_text(f"{SECRET} 2 0 0\n")
    (outside / "square.off").write_text(SQUARE_OFF)
    (outside / "folder").mkdir()
    (outside / "folder" / "inner.off").write_text(SQUARE_OFF)
    for stem, companion in (("node_out", "node"), ("neigh_out", "neigh"),
                            ("poly_out", "poly")):
        io.write(root / f"{stem}.ele", run.mesh, exact=True)  # .node .ele .neigh .poly
        (root / f"{stem}.{companion}").unlink()
        os.symlink(outside / f"secret.{companion}", root / f"{stem}.{companion}")
    io.write(root / "face_out.ele", cube_grid(1, 1, 1), format="tetgen")  # TetGen's .face
    (outside / "secret.face").write_text(f"{SECRET} 0\n")
    (root / "face_out.face").unlink()
    os.symlink(outside / "secret.face", root / "face_out.face")
    (root / "zero.poly").write_text("0 2 0 0\n0 0\n0\n")
    os.symlink(outside / "secret.node", root / "zero.node")
    os.symlink(outside / "square.off", root / "linked_out.off")
    os.symlink(outside / "folder", root / "folder_out")
    os.symlink(outside / "missing.off", root / "dangling_out.off")
    (root / "dangling.ele").write_text("1 3 0\n0 0 1 2\n")
    os.symlink(outside / "missing.node", root / "dangling.node")
    (root / "meshes").mkdir()
    (root / "meshes" / "square.off").write_text(SQUARE_OFF)
    os.symlink(root / "meshes" / "square.off", root / "linked_in.off")
    (root / "secret.txt").write_text(f"{SECRET} is the password here\n")
    (root / "secret.off").write_text(f"OFF\n{SECRET} 1 0\n")
    (root / "keyword.off").write_text(f"{SECRET}\n4 2 0\n")
    (root / "notes.trace.jsonl").write_text(f'{{"format": "{SECRET}"}}\n')
    (root / "vocabulary.txt").write_text("0 0 1 0\n")
    (root / "scene.xdmf").write_text("<Xdmf/>\n")
    (root / ".private").mkdir()
    (root / ".private" / "hidden.off").write_text(SQUARE_OFF)
    write_trace(root / "linked.trace.jsonl", run.trace)
    return root


@pytest.fixture(scope="module")
def server(served: Path) -> Iterator[MeshServer]:
    with running(ServeOptions(served, port=0, time_limit=60)) as server:
        yield server


def leaked(page: str) -> bool:
    return SECRET.lower() in html.unescape(page).lower()


# ---------------------------------------------------------------------------------------
# nothing outside DIR is listed or read
# ---------------------------------------------------------------------------------------
def test_index_lists_no_link_out_of_the_directory(server: MeshServer) -> None:
    """Files, meshes with a companion, folders and dangling links pointing out of DIR
    are not listed; links inside DIR are; XDMF and hidden folders are not."""
    status, page = request(server, "GET", "/")
    assert status == 200
    links = re.findall(r'href="/view\?(?:file|trace)=([^"]+)"', page)
    assert "linked_in.off" in links and "meshes/square.off" in links
    for name in ("node_out.ele", "neigh_out.ele", "poly_out.ele", "face_out.ele", "zero.poly",
                 "linked_out.off", "folder_out/inner.off", "dangling_out.off",
                 "dangling.ele", "scene.xdmf", ".private/hidden.off"):
        assert name not in links, name
    assert "folder_out" not in page and "outside" not in page


@pytest.mark.parametrize("name", ["node_out.ele", "neigh_out.ele", "poly_out.ele",
                                  "face_out.ele", "zero.poly", "dangling.ele"])
def test_companion_out_of_the_directory_is_refused_and_not_read(server: MeshServer,
                                                               name: str) -> None:
    """A mesh whose .node / .neigh / .poly / .face (or a dangling link) points out of DIR: 403
    naming the companion, and nothing of the secret file on the page."""
    status, page = request(server, "GET", f"/view?file={name}")
    assert status == 403, alert(page)
    assert "lies outside the served directory" in alert(page)
    assert not leaked(page)


@pytest.mark.parametrize("path", ["/view?file=linked_out.off", "/view?file=dangling_out.off",
                                  "/view?file=folder_out/inner.off",
                                  "/view?file=.private/hidden.off",
                                  "/view?file=meshes/../linked_out.off",
                                  "/view?trace=folder_out/inner.off"])
def test_links_out_and_hidden_names_are_not_found(server: MeshServer, path: str) -> None:
    """A link out of DIR (file, folder, dangling), a hidden name or a climb: 404."""
    status, page = request(server, "GET", path)
    assert status == 404 and not leaked(page)


LONG = "a" * 300
DEEP = "a/" * 5000


@pytest.mark.parametrize("path", [
    f"/view?file={LONG}.off", f"/view?file={DEEP}x.off", f"/view?file=meshes/{LONG}.off",
    f"/view?file={'é' * 200}.off", f"/view?file=a/b/c/d/{LONG}.off",
    f"/view?trace={LONG}.trace.jsonl", f"/view?trace={DEEP}x.trace.jsonl",
    f"/view?file=meshes/square.off&trace={DEEP}x.trace.jsonl",
    f"/view?file={DEEP}x.off&trace=linked.trace.jsonl",
])
def test_long_names_and_deep_paths_are_not_found(server: MeshServer, served: Path,
                                                  path: str) -> None:
    """A 300-character name (or one past 255 bytes of UTF-8), a 5,000-level path, a path
    deeper than the index lists: 404 naming the request, shortened, and no path of the
    server's on the page (was 500 quoting "File name too long: '/tmp/…'")."""
    status, page = request(server, "GET", urllib.parse.quote(path, safe="/?=&"))
    assert status == 404, alert(page)
    text = html.unescape(page)
    assert "no file" in alert(page) and len(alert(page)) < 400
    for absolute in (str(served), str(served.resolve()), tempfile.gettempdir() + os.sep,
                     str(Path.cwd())):
        assert absolute not in text, absolute


def test_links_inside_the_directory_are_served(server: MeshServer) -> None:
    """A symlink to a file inside DIR is read as that file."""
    status, _ = request(server, "GET", "/view?file=linked_in.off")
    assert status == 200


def test_xdmf_is_not_read(server: MeshServer) -> None:
    """XDMF names its data files by any path: the server refuses it (403) unread."""
    status, page = request(server, "GET", "/view?file=scene.xdmf")
    assert status == 403 and "XDMF" in alert(page)


# ---------------------------------------------------------------------------------------
# error pages name file, line and problem, never the file's text
# ---------------------------------------------------------------------------------------
@pytest.mark.parametrize(("path", "where"), [
    ("/view?file=secret.txt", "secret.txt:1: "),
    ("/view?file=secret.off", "secret.off:2: "),
    ("/view?file=keyword.off", "keyword.off:1: "),
    ("/view?trace=notes.trace.jsonl", "notes.trace.jsonl:1: "),
])
def test_error_pages_do_not_echo_file_text(server: MeshServer, path: str, where: str
                                           ) -> None:
    """A non-mesh file with a mesh extension (or a trace's): 400, the file, the line and
    the kind of problem, HTML-escaped, with the quoted text replaced and none of the
    file's text."""
    status, page = request(server, "GET", path)
    assert status == 400
    message = html.unescape(alert(page))
    assert message.startswith(where) and NOT_SHOWN in message, message
    assert not leaked(page)
    assert str(server.options.directory.resolve()) not in message


def test_vocabulary_quotes_stay(server: MeshServer) -> None:
    """A quote of the format's own words (none of them on the offending line) is kept."""
    status, page = request(server, "GET", "/view?file=vocabulary.txt")
    assert status == 400
    assert "'x1 y1 x2 y2 x3 y3'" in html.unescape(alert(page))


def test_a_bad_upload_is_not_echoed_either(server: MeshServer) -> None:
    """Uploads follow the same rule (the page never quotes a file)."""
    from helpers.server_client import upload

    status, page = upload(server, [("pw.txt", f"{SECRET} a b\n".encode())],
                          action="triangulate")
    assert status == 400 and not leaked(page)
    assert html.unescape(alert(page)).startswith("pw.txt:1: a triangle line is")


# ---------------------------------------------------------------------------------------
# the pieces
# ---------------------------------------------------------------------------------------
def test_companion_names() -> None:
    """What a reader opens beside a file, by its extension (case of the stem kept)."""
    assert companion_names("a.1.ele") == ("a.1.node", "a.1.neigh", "a.1.poly", "a.1.face")
    assert companion_names("A.ELE") == ("A.ele", "A.node", "A.neigh", "A.poly", "A.face")
    assert companion_names("x.poly") == ("x.node",)
    assert companion_names("x.node") == () and companion_names("x.off") == ()


@pytest.mark.parametrize(("text", "expected"), [
    ("a/b.off", PurePosixPath("a/b.off")), ("a//./b.off", PurePosixPath("a/b.off")),
    ("/etc/passwd", None), ("../x.off", None), ("a/../b.off", None), (".git/config", None),
    ("a/.b.off", None), ("", None), (".", None), ("a\x00b", None),
    ("a/b/c.off", PurePosixPath("a/b/c.off")), ("a/b/c/d.off", None),
    ("a" * 255, PurePosixPath("a" * 255)), ("a" * 256, None), ("é" * 128, None),
])
def test_relative_names(text: str, expected: PurePosixPath | None) -> None:
    """Only plain relative names: no absolute path, climb, hidden part or NUL, no deeper
    than the index lists (two folders), no part past 255 bytes."""
    assert relative_name(text) == expected


@pytest.mark.parametrize(("problem", "line", "expected"), [
    ("found 'secret words'", "a secret b", f"found {NOT_SHOWN}"),
    ("expected 'x y', found 'a'", "a b", "expected 'x y', found " + NOT_SHOWN),
    ("expected 'x y'", None, f"expected {NOT_SHOWN}"),
    ("the mesh's header: 'secret'", "secret", f"the mesh's header: {NOT_SHOWN}"),
    ("bytes b'secret' here", "nothing", f"bytes b{NOT_SHOWN}"),
    ("unclosed 'secret", "nothing", f"unclosed {NOT_SHOWN}"),
    ("""found 'it\\'s "Secret"'""", "secret", f"found {NOT_SHOWN}"),
    ("found ''", "x", f"found {NOT_SHOWN}"),
    ("no quotes at all", None, "no quotes at all"),
])
def test_quotes_of_file_text_are_hidden(problem: str, line: str | None, expected: str
                                        ) -> None:
    """A quote is kept only when none of its words is on the offending line; bytes,
    unclosed or empty quotes are hidden; an apostrophe in a word is not a quote."""
    assert without_file_text(problem, line) == expected


def test_offending_line_in_both_numberings(tmp_path: Path) -> None:
    """The line split on \\n and as str.splitlines splits it (the trace reader's)."""
    path = tmp_path / "lines.txt"
    path.write_bytes(b"a\rB\nc\n" + b"x" * 70000 + b"\nd\n")
    assert offending_line(str(path), 1) == "a\na\rb\n"
    assert offending_line(str(path), 2) == "b\nc\n"
    assert offending_line(str(path), 3) is None  # too long: every quote will be hidden
    assert offending_line(str(path), None) is None
    assert offending_line(str(tmp_path / "missing"), 1) is None


def test_other_read_failures_are_named_by_kind() -> None:
    """A failure that is not a FormatError shows its kind, not its message."""
    message = failure_message(KeyError(SECRET), "m.vtk", ())
    assert message == "m.vtk: cannot be read (KeyError; the reader's message is not shown)"
    message = failure_message(PermissionError(13, "Permission denied", SECRET), "m.vtk", ())
    assert message == "m.vtk: cannot read it (Permission denied)"
