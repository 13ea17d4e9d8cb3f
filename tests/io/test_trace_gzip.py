"""gzip-compressed trace files: written when the name ends in .gz, with the same bytes for
the same trace; read by their magic bytes, line by line; corrupt or truncated gzip data is
a FormatError naming the file (and the line being read)."""

from __future__ import annotations

import gzip
from pathlib import Path

import pytest

from geomexact import mesh_from_triangles
from geomexact.errors import FormatError
from geomexact.io.files import GZIP_MAGIC, read_lines
from geomexact.io.trace_file import read_trace, trace_text, write_trace
from geomexact.mesh2d.refinement.api import refine
from geomexact.mesh2d.refinement.criteria import MaxArea
from geomexact.trace.record import Trace


@pytest.fixture(scope="module")
def trace() -> Trace:
    square = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)])
    return refine(square, MaxArea("1/64"), method="bisection").trace


def test_a_gz_trace_round_trips_and_is_compressed(tmp_path: Path, trace: Trace) -> None:
    path = tmp_path / "run.trace.jsonl.gz"
    write_trace(path, trace)
    data = path.read_bytes()
    assert data[:2] == GZIP_MAGIC
    assert gzip.decompress(data).decode() == trace_text(trace)
    assert read_trace(path) == trace


def test_the_same_trace_gives_byte_identical_gz_files(tmp_path: Path, trace: Trace) -> None:
    first, second = tmp_path / "a.jsonl.gz", tmp_path / "sub" / "b.jsonl.gz"
    second.parent.mkdir()
    write_trace(first, trace)
    write_trace(second, trace)
    assert first.read_bytes() == second.read_bytes()
    assert first.read_bytes()[4:8] == b"\0\0\0\0"  # no time stamp
    assert b"a.jsonl" not in first.read_bytes()  # no file name


def test_gzip_is_recognised_by_its_bytes_not_its_name(tmp_path: Path, trace: Trace) -> None:
    packed, plain = tmp_path / "packed.gz", tmp_path / "plain.jsonl.gz"
    write_trace(packed, trace)
    renamed = tmp_path / "renamed.jsonl"
    renamed.write_bytes(packed.read_bytes())
    plain.write_text(trace_text(trace))  # a .gz name on plain text
    assert read_trace(renamed) == trace and read_trace(plain) == trace


def test_a_corrupt_gz_trace_names_the_file(tmp_path: Path, trace: Trace) -> None:
    path = tmp_path / "run.trace.jsonl.gz"
    write_trace(path, trace)
    data = bytearray(path.read_bytes())
    for index in range(40, 80):
        data[index] ^= 0xFF
    bad = tmp_path / "bad.jsonl.gz"
    bad.write_bytes(bytes(data))
    with pytest.raises(FormatError, match=r"bad\.jsonl\.gz:[0-9]+: corrupt gzip data") as caught:
        read_trace(bad)
    assert caught.value.path == str(bad)


def test_a_gz_trace_with_a_wrong_checksum_is_corrupt(tmp_path: Path, trace: Trace) -> None:
    path = tmp_path / "run.trace.jsonl.gz"
    write_trace(path, trace)
    data = bytearray(path.read_bytes())
    data[-8] ^= 0xFF  # the CRC-32 of the data
    path.write_bytes(bytes(data))
    with pytest.raises(FormatError, match="corrupt gzip data"):
        read_trace(path)


def test_a_truncated_gz_trace_names_the_file_and_line(tmp_path: Path, trace: Trace) -> None:
    path = tmp_path / "run.trace.jsonl.gz"
    write_trace(path, trace)
    data = path.read_bytes()
    cut = tmp_path / "cut.jsonl.gz"
    cut.write_bytes(data[: len(data) // 2])
    with pytest.raises(FormatError, match=r"cut.jsonl.gz:\d+: truncated gzip file") as caught:
        read_trace(cut)
    assert caught.value.line is not None and caught.value.line > 1
    only_header = tmp_path / "header.gz"
    only_header.write_bytes(data[:5])
    with pytest.raises(FormatError, match=r"header\.gz"):
        read_trace(only_header)


def test_plain_readers_do_not_decompress(tmp_path: Path) -> None:
    """Only trace reading decompresses; other readers see the bytes as they are."""
    path = tmp_path / "x.txt"
    path.write_bytes(gzip.compress(b"hello\n", mtime=0))
    with pytest.raises(FormatError, match="not UTF-8"):
        list(read_lines(path))
    assert list(read_lines(path, decompress=True)) == [(1, "hello")]
