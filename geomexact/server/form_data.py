"""Reading an upload's ``multipart/form-data`` body (RFC 7578) in one pass: time linear in
its size, at most :data:`MAX_FORM_PARTS` parts, each part's headers at most
:data:`MAX_PART_HEADER_BYTES`.  (The standard library's e-mail parser spent about 0.3 ms
a part, outside any job's limits: a 16 MB body of small parts took 50 to 100 s of the
server's time.)"""

from __future__ import annotations

import re
from http import HTTPStatus

from geomexact.server.bounded import JobFailed

MAX_FORM_PARTS = 64
"""The most parts an upload may have (the form has six fields and the files of a mesh)."""

MAX_PART_HEADER_BYTES = 8192
"""The longest header block of one part."""

MAX_BOUNDARY_CHARS = 70  # RFC 2046
_TOKEN = r"[!#$%&'*+.^_`|~0-9A-Za-z-]+"
_PARAMETER = re.compile(rf'\s*({_TOKEN})\s*=\s*("(?:[^"\\]|\\.)*"|[^;]*?)\s*(?:;|$)')
_ESCAPE = re.compile(r"\\(.)")
_IDENTITY_ENCODINGS = ("", "binary", "8bit", "7bit")


def _bad(message: str) -> JobFailed:
    return JobFailed(HTTPStatus.BAD_REQUEST, f"the upload is not valid form data: {message}")


def header_parameters(value: str) -> tuple[str, dict[str, str]]:
    """A header value's first item (lower case) and its ``name=value`` parameters (names in
    lower case, quoted values unquoted)."""
    first, _, rest = value.partition(";")
    parameters: dict[str, str] = {}
    for match in _PARAMETER.finditer(rest):
        name, text = match.group(1).lower(), match.group(2)
        if text.startswith('"') and text.endswith('"') and len(text) >= 2:
            text = _ESCAPE.sub(r"\1", text[1:-1])
        parameters.setdefault(name, text)
    return first.strip().lower(), parameters


def _boundary(content_type: str) -> bytes:
    kind, parameters = header_parameters(content_type)
    if kind != "multipart/form-data":
        raise JobFailed(HTTPStatus.BAD_REQUEST, "the upload is not multipart/form-data")
    boundary = parameters.get("boundary", "")
    if not 0 < len(boundary) <= MAX_BOUNDARY_CHARS or not boundary.isascii():
        raise _bad("its Content-Type has no valid boundary (1 to 70 ASCII characters)")
    return boundary.encode("ascii")


def _part_headers(block: bytes) -> dict[str, str]:
    headers: dict[str, str] = {}
    for line in block.decode("utf-8", "replace").split("\r\n"):
        name, colon, value = line.partition(":")
        if not colon:
            raise _bad("a part has a header line without a colon")
        headers.setdefault(name.strip().lower(), value.strip())
    return headers


def _parts(body: bytes, boundary: bytes) -> list[tuple[dict[str, str], bytes]]:
    """The (headers, content) of each part, in order."""
    delimiter = b"--" + boundary
    inner = b"\r\n" + delimiter
    if body.startswith(delimiter):
        position = len(delimiter)
    else:  # a preamble before the first delimiter
        first = body.find(inner)
        if first < 0:
            raise _bad("no part starts with its boundary")
        position = first + len(inner)
    parts: list[tuple[dict[str, str], bytes]] = []
    while not body.startswith(b"--", position):  # "--" after a delimiter closes the body
        line_end = body.find(b"\r\n", position, position + MAX_PART_HEADER_BYTES)
        if line_end < 0 or body[position:line_end].strip(b" \t"):
            raise _bad("a boundary line has more than the boundary")
        if len(parts) == MAX_FORM_PARTS:
            raise _bad(f"it has more than {MAX_FORM_PARTS} parts")
        start = line_end + 2
        if body.startswith(b"\r\n", start):  # a part without headers
            headers: dict[str, str] = {}
            content_start = start + 2
        else:
            end = body.find(b"\r\n\r\n", start, start + MAX_PART_HEADER_BYTES)
            if end < 0:
                raise _bad(f"a part's headers do not end within {MAX_PART_HEADER_BYTES:,} "
                           "bytes")
            headers = _part_headers(body[start:end])
            content_start = end + 4
        content_end = body.find(inner, content_start)
        if content_end < 0:
            raise _bad("it ends inside a part (no closing boundary)")
        parts.append((headers, body[content_start:content_end]))
        position = content_end + len(inner)
    return parts


def parse_multipart(content_type: str, body: bytes) -> tuple[list[tuple[str, bytes]],
                                                             dict[str, str]]:
    """The uploaded files (name, bytes) and text fields of a ``multipart/form-data``
    body: a part with a ``filename`` is a file (an empty file input, no name and no bytes,
    is left out), one without a text field (UTF-8); parts without a ``name`` are ignored.
    :class:`~geomexact.server.bounded.JobFailed` 400 for a body that is not such form data,
    has more than :data:`MAX_FORM_PARTS` parts or a transfer encoding."""
    files: list[tuple[str, bytes]] = []
    fields: dict[str, str] = {}
    for headers, data in _parts(body, _boundary(content_type)):
        encoding = headers.get("content-transfer-encoding", "").lower()
        if encoding not in _IDENTITY_ENCODINGS:
            raise _bad(f"a part is sent in {encoding!r} transfer encoding (send its bytes)")
        kind, parameters = header_parameters(headers.get("content-disposition", ""))
        name = parameters.get("name")
        if kind != "form-data" or name is None:
            continue
        filename = parameters.get("filename")
        if filename is not None:
            if filename or data:
                files.append((filename or "upload", data))
        else:
            fields[name] = data.decode("utf-8", "replace")
    return files, fields
