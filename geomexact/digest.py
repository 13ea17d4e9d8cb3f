"""Content digests of meshes: a sum of per-element hashes modulo 2^128.

The digest of a mesh is the sum, modulo 2^128, of one 128-bit BLAKE2b hash per element
(vertex with its exact coordinates, triangle or tetrahedron with its canonical vertex tuple,
constrained segment with its marker, element attributes).  A sum is order-independent, so it
depends only on the mesh's content, never on its history or on the process hash seed, and
adding or removing an element updates it in O(1).  See ``specs/snapshot.md``.
"""

from __future__ import annotations

import struct
from collections.abc import Sequence
from hashlib import blake2b

import gmpy2

from geomexact.numbers import Rational

MODULUS = 1 << 128
_MASK = MODULUS - 1


def _hash(payload: bytes) -> int:
    return int.from_bytes(blake2b(payload, digest_size=16).digest(), "little")


def _rational_text(value: Rational) -> str:
    return f"{value.numerator}/{value.denominator}"


_ID = struct.Struct("<Q").pack
_to_binary = gmpy2.to_binary


def vertex_hash(vertex: int, coordinates: Sequence[Rational]) -> int:
    """Hash of vertex ``vertex`` at the exact ``coordinates``: BLAKE2b-128 with
    personalisation ``b"vertex"`` of the id (little-endian u64) followed by each coordinate
    in gmpy2's portable, self-delimiting ``to_binary`` encoding."""
    payload = _ID(vertex)
    for coordinate in coordinates:
        payload += _to_binary(coordinate)
    return int.from_bytes(
        blake2b(payload, digest_size=16, person=b"vertex").digest(), "little"
    )


_CELL_FORMATS = {3: struct.Struct("<3Q").pack, 4: struct.Struct("<4Q").pack}


def cell_hash(cell: Sequence[int]) -> int:
    """Hash of a canonical cell (triangle or tetrahedron vertex tuple): BLAKE2b-128 with
    personalisation ``b"cell"`` of the ids as little-endian unsigned 64-bit integers."""
    return int.from_bytes(
        blake2b(_CELL_FORMATS[len(cell)](*cell), digest_size=16, person=b"cell").digest(),
        "little",
    )


def segment_hash(u: int, v: int, marker: int) -> int:
    """Hash of the constrained segment {u, v} (u < v) with its boundary ``marker``."""
    return _hash(f"s{u},{v}:{marker}".encode())


def attribute_hash(kind: str, key: Sequence[int], values: Sequence[object]) -> int:
    """Hash of an attribute record (``kind`` names the table, ``key`` the element)."""
    text = ",".join(_rational_text(v) if hasattr(v, "denominator") else str(v) for v in values)
    return _hash(f"a{kind}:{','.join(map(str, key))}:{text}".encode())


def combine(digest: int, element: int) -> int:
    """Digest after adding an element with hash ``element``."""
    return (digest + element) & _MASK


def remove(digest: int, element: int) -> int:
    """Digest after removing an element with hash ``element``."""
    return (digest - element) & _MASK


def digest_text(digest: int) -> str:
    """The 32-hex-digit form used in traces and reports."""
    return f"{digest:032x}"
