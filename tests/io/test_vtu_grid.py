"""geomexact's binary VTU writer (:mod:`geomexact.io.vtu_grid`): every array read back by an
independent decoder (base64, the UInt64 block header, zlib: no geomexact code) and by
meshio, empty and multi-block arrays included."""

from __future__ import annotations

import base64
import re
import struct
import zlib
from pathlib import Path

import numpy as np
import pytest

from geomexact.io.vtu_grid import BLOCK_BYTES, binary_vtu

_TYPES = {"Float64": "<f8", "Int32": "<i4", "Int64": "<i8", "UInt8": "u1"}


def _decoded(text: str) -> dict[str, np.ndarray]:
    """Each DataArray of a VTU document, decoded by hand."""
    arrays = {}
    for vtu_type, name, body in re.findall(
            r'<DataArray type="(\w+)" Name="(\w+)"[^>]*format="binary">\s*([^<]*?)\s*'
            r"</DataArray>", text):
        # the header's base64 ends where its length says: 3 + count words of 8 bytes
        count = struct.unpack("<Q", base64.b64decode(body[:12])[:8])[0]
        header_chars = 4 * -(-(8 * (3 + count)) // 3)
        header = struct.unpack(f"<{3 + count}Q", base64.b64decode(body[:header_chars]))
        blocks, size, last, sizes = header[0], header[1], header[2], header[3:]
        data = base64.b64decode(body[header_chars:])
        raw, at = b"", 0
        for n, compressed in enumerate(sizes):
            chunk = zlib.decompress(data[at:at + compressed])
            assert len(chunk) == (last if n == blocks - 1 else size)
            raw += chunk
            at += compressed
        assert at == len(data) and blocks == len(sizes) and size == BLOCK_BYTES
        arrays[name] = np.frombuffer(raw, dtype=_TYPES[vtu_type])
    return arrays


@pytest.mark.parametrize("count", [0, 1, 5000])
def test_binary_vtu_arrays_read_back(tmp_path: Path, count: int) -> None:
    chooser = np.random.default_rng(count)
    points = chooser.random((count + 3, 3))
    tetrahedra = chooser.integers(0, count + 3, size=(count, 4)).astype(np.int32)
    offsets = np.arange(4, 4 * count + 1, 4, dtype=np.int64)
    types = np.full(count, 10, dtype=np.uint8)
    quality = chooser.random(count) * 90
    text = binary_vtu(points, types, tetrahedra.ravel(), offsets, {"q": quality}).decode()
    assert 'compressor="vtkZLibDataCompressor"' in text and 'header_type="UInt64"' in text
    arrays = _decoded(text)
    assert (arrays["Points"].reshape(-1, 3) == points).all()
    assert (arrays["connectivity"] == tetrahedra.ravel()).all()
    assert (arrays["offsets"] == offsets).all() and (arrays["types"] == 10).all()
    assert (arrays["q"] == quality).all()
    if count > 2000:  # several blocks
        assert len(tetrahedra.tobytes()) > 2 * BLOCK_BYTES
    if count:
        import meshio

        path = tmp_path / "grid.vtu"
        path.write_text(text)
        mesh = meshio.read(path)
        assert (mesh.points == points).all()
        assert (mesh.cells_dict["tetra"] == tetrahedra).all()
        assert (mesh.cell_data["q"][0] == quality).all()
