"""An upload's form data (issue 27, item 8): read in one linear pass with at most 64 parts
(the e-mail parser it replaces spent ~0.3 ms a part in the server, outside the jobs'
limits: a 16 MB body of small parts took 50 to 100 s); the same files and fields as the
e-mail parser reads from what browsers and ``requests`` send."""

from __future__ import annotations

import email.parser
import email.policy
import uuid
from pathlib import Path

import pytest
from helpers.server_client import SQUARE_OFF, Log, alert, multipart, request, running, upload

from geomexact.server import JobFailed, ServeOptions, parse_multipart
from geomexact.server.form_data import MAX_FORM_PARTS, header_parameters


def email_reading(content_type: str, body: bytes) -> tuple[list[tuple[str, bytes]],
                                                          dict[str, str]]:
    """The files and fields the standard library's e-mail parser reads (the reference)."""
    head = f"Content-Type: {content_type}\r\nMIME-Version: 1.0\r\n\r\n".encode("latin-1")
    message = email.parser.BytesParser(policy=email.policy.HTTP).parsebytes(head + body)
    files: list[tuple[str, bytes]] = []
    fields: dict[str, str] = {}
    for part in message.iter_parts():
        name = part.get_param("name", header="content-disposition")
        if not isinstance(name, str):
            continue
        filename = part.get_filename()
        payload = part.get_payload(decode=True)
        data = payload if isinstance(payload, bytes) else b""
        if filename is not None:
            if filename or data:
                files.append((filename or "upload", data))
        else:
            fields[name] = data.decode("utf-8", "replace")
    return files, fields


def browser_body(boundary: str, parts: list[tuple[str, str | None, bytes]],
                 preamble: bytes = b"", epilogue: bytes = b"") -> bytes:
    """A body as a browser builds it: (name, filename or None, bytes) per part."""
    chunks = [preamble]
    for name, filename, data in parts:
        disposition = f'form-data; name="{name}"'
        if filename is not None:
            disposition += f'; filename="{filename}"'
            head = (f"--{boundary}\r\nContent-Disposition: {disposition}\r\n"
                    "Content-Type: application/octet-stream\r\n\r\n")
        else:
            head = f"--{boundary}\r\nContent-Disposition: {disposition}\r\n\r\n"
        chunks.append(head.encode() + data + b"\r\n")
    chunks.append(f"--{boundary}--\r\n".encode() + epilogue)
    return b"".join(chunks)


BOUNDARY = "----WebKitFormBoundary7MA4YWxkTrZu0gW"
CASES = {
    "files and fields": [("files", "a.ele", b"1 3 0\n0 0 1 2\n"), ("files", "a.node", b"3 2\n"),
                         ("action", None, b"refine"), ("value", None, b"1/300")],
    "empty file input": [("files", "", b""), ("action", None, b"triangulate")],
    "bytes like delimiters": [("files", "x.off", b"--" + BOUNDARY.encode()[:-1] + b"\r\n--\r\n"),
                              ("action", None, b"")],
    "crlf at the ends": [("files", "y.off", b"\r\nOFF\r\n\r\n"), ("note", None, "é∑".encode())],
    "unnamed file": [("files", "", b"OFF\n")],
}


@pytest.mark.parametrize("case", sorted(CASES))
@pytest.mark.parametrize(("preamble", "epilogue"), [(b"", b""), (b"ignored\r\n", b"tail")])
def test_same_reading_as_the_email_parser(case: str, preamble: bytes, epilogue: bytes
                                          ) -> None:
    """Browser-built bodies (a preamble and an epilogue too): the files and fields the
    e-mail parser reads."""
    content_type = f"multipart/form-data; boundary={BOUNDARY}"
    body = browser_body(BOUNDARY, CASES[case], preamble, epilogue)
    assert parse_multipart(content_type, body) == email_reading(content_type, body)


def test_test_client_bodies_and_quoted_boundaries() -> None:
    """The test client's bodies, and a quoted boundary with a space (RFC 2046)."""
    body, content_type = multipart([("a.off", b"OFF\n"), ("", b"")], {"action": "refine"})
    assert parse_multipart(content_type, body) == email_reading(content_type, body)
    quoted = browser_body("a b:c", [("action", None, b"refine")])
    content_type = 'multipart/form-data; charset=utf-8; boundary="a b:c"'
    assert parse_multipart(content_type, quoted) == ([], {"action": "refine"})


def test_header_parameters() -> None:
    """Quoted values unquoted (backslash escapes), names in lower case, the first kept."""
    assert header_parameters('form-data; NAME="a\\"b"; filename=x.off; name=c') == (
        "form-data", {"name": 'a"b', "filename": "x.off"})
    assert header_parameters("Multipart/Form-Data") == ("multipart/form-data", {})


def parts_body(count: int) -> tuple[str, bytes]:
    boundary = uuid.uuid4().hex
    part = f'--{boundary}\r\nContent-Disposition: form-data; name="f"\r\n\r\nx\r\n'.encode()
    return (f"multipart/form-data; boundary={boundary}",
            part * count + f"--{boundary}--\r\n".encode())


def test_at_most_64_parts() -> None:
    """64 parts are read; 65 are refused with a 400 naming the limit, and so is a 16 MB
    body of 200,000 small parts (the e-mail parser spent 50 to 100 s on it)."""
    content_type, body = parts_body(MAX_FORM_PARTS)
    assert parse_multipart(content_type, body) == ([], {"f": "x"})
    for count in (MAX_FORM_PARTS + 1, 16 * 1024 * 1024 // 83):
        content_type, body = parts_body(count)
        with pytest.raises(JobFailed) as caught:
            parse_multipart(content_type, body)
        assert caught.value.status == 400
        assert f"more than {MAX_FORM_PARTS} parts" in caught.value.message


@pytest.mark.parametrize(("content_type", "body", "expected"), [
    ("multipart/form-data", b"--x\r\n\r\n\r\n--x--", "no valid boundary"),
    (f"multipart/form-data; boundary={'b' * 71}", b"", "no valid boundary"),
    ("multipart/form-data; boundary=x", b"no delimiter at all", "no part starts"),
    ("multipart/form-data; boundary=x", b"--x\r\nContent-Disposition: form-data; name=a"
                                        b"\r\n\r\nnever closed", "no closing boundary"),
    ("multipart/form-data; boundary=x", b"--x\r\n" + b"X-A: 1\r\n" * 2000 + b"\r\n",
     "headers do not end"),
    ("multipart/form-data; boundary=x", b"--x\r\nno colon\r\n\r\nv\r\n--x--",
     "without a colon"),
    ("multipart/form-data; boundary=x", b"--xy\r\n\r\nv\r\n--x--", "more than the boundary"),
    ("multipart/form-data; boundary=x", b"--x\r\nContent-Transfer-Encoding: base64\r\n"
                                        b"Content-Disposition: form-data; name=a\r\n\r\n"
                                        b"eA==\r\n--x--", "transfer encoding"),
    ("text/plain; boundary=x", b"--x--", "not multipart/form-data"),
])
def test_bad_form_data_is_a_400_naming_the_problem(content_type: str, body: bytes,
                                                   expected: str) -> None:
    with pytest.raises(JobFailed) as caught:
        parse_multipart(content_type, body)
    assert caught.value.status == 400 and expected in caught.value.message


def test_a_16_mb_upload_of_small_parts_is_refused_at_once(tmp_path: Path) -> None:
    """Through the server (upload limit 17 MB): 400 naming the part limit; the request's
    own 60 s timeout is the hang guard (the e-mail parser took 50 to 100 s of the
    server's time on this body)."""
    (tmp_path / "square.off").write_text(SQUARE_OFF)
    log = Log()
    content_type, body = parts_body(16 * 1024 * 1024 // 83)
    with running(ServeOptions(tmp_path, port=0, max_upload_bytes=17 * 1024 * 1024),
                 log) as server:
        status, page = request(server, "POST", "/upload", body,
                               {"Content-Type": content_type}, timeout=60)
        assert status == 400 and f"more than {MAX_FORM_PARTS} parts" in alert(page)
        assert server.upload_slots.in_use == 0
        status, page = upload(server, [("a.off", SQUARE_OFF.encode())], action="triangulate")
        assert status == 200, alert(page)
    assert "Traceback" not in log.getvalue()
