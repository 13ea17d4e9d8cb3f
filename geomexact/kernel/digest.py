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

from geomexact.kernel.numbers import Rational

MODULUS = 1 << 128
_MASK = MODULUS - 1


def _hash(payload: bytes) -> int:
    return int.from_bytes(blake2b(payload, digest_size=16).digest(), "little")


def _rational_text(value: Rational) -> str:
    # gmpy2 writes the digits: Python's int -> str refuses more than 4300 of them
    return f"{gmpy2.mpz(value.numerator)}/{gmpy2.mpz(value.denominator)}"


_ID = struct.Struct("<Q").pack
_to_binary = gmpy2.to_binary
_VERTEX_HASHER = blake2b(digest_size=16, person=b"vertex")


def vertex_hash(vertex: int, coordinates: Sequence[Rational]) -> int:
    """Hash of vertex ``vertex`` at the exact ``coordinates``: BLAKE2b-128 with
    personalisation ``b"vertex"`` of the id (little-endian u64) followed by each coordinate
    in gmpy2's portable, self-delimiting ``to_binary`` encoding."""
    payload = _ID(vertex)
    for coordinate in coordinates:
        payload += _to_binary(coordinate)
    hasher = _VERTEX_HASHER.copy()  # cheaper than a new personalised BLAKE2b
    hasher.update(payload)
    return int.from_bytes(hasher.digest(), "little")


# Cell hashes mix per-vertex 64-bit keys (BLAKE2b of the id, computed once per id and
# cached) with fixed odd 128-bit multipliers, then a xorshift-multiply finaliser: about half
# the cost of hashing the packed ids with BLAKE2b, and cells are hashed on every step.
_POSITION_MULTIPLIERS = (
    0x9E3779B97F4A7C15F39CC0605CEDC835,
    0xC2B2AE3D27D4EB4F165667B19E3779F9,
    0xD6E8FEB86659FD93A1E5B0C2E1B7C2D9,
    0xA0761D6478BD642FE7037ED1A0B428DB,
)
_M0, _M1, _M2, _M3 = _POSITION_MULTIPLIERS
FINAL_MULTIPLIER = _FINAL_MULTIPLIER = 0x94D049BB133111EBBF58476D1CE4E5B9
_VERTEX_KEYS: list[int] = []
VERTEX_KEYS = _VERTEX_KEYS
"""The cached vertex keys by id (read only; :func:`vertex_key` extends it), for kernels that
inline :func:`cell_hash`."""
TRIANGLE_MULTIPLIERS = (_M0, _M1, _M2)
"""The position multipliers of a triangle's cell hash, for kernels that inline it."""


def vertex_key(vertex: int) -> int:
    """The 64-bit key of a vertex id: the first 8 bytes (little endian) of BLAKE2b with
    personalisation ``b"vkey"`` of the id as a little-endian u64."""
    keys = _VERTEX_KEYS
    while len(keys) <= vertex:
        keys.append(int.from_bytes(
            blake2b(_ID(len(keys)), digest_size=8, person=b"vkey").digest(), "little"))
    return keys[vertex]


def cell_hash(cell: Sequence[int]) -> int:
    """Hash of a canonical cell (triangle or tetrahedron vertex tuple):
    ``x = Σ key(cell[i])·M_i mod 2^128; x ^= x >> 61; h = x·M_f mod 2^128`` (constants in
    ``specs/snapshot.md``)."""
    keys = _VERTEX_KEYS
    try:
        if len(cell) == 3:
            a, b, c = cell
            x = (keys[a] * _M0 + keys[b] * _M1 + keys[c] * _M2) & _MASK
        else:
            x = sum(keys[v] * m for v, m in zip(cell, _POSITION_MULTIPLIERS, strict=True))
            x &= _MASK
    except IndexError:
        vertex_key(max(cell))
        return cell_hash(cell)
    x ^= x >> 61
    return (x * _FINAL_MULTIPLIER) & _MASK


def segment_hash(u: int, v: int, marker: int) -> int:
    """Hash of the constrained segment {u, v} (u < v) with its boundary ``marker``."""
    return _hash(f"s{u},{v}:{marker}".encode())


def attribute_hash(kind: str, key: Sequence[int], values: Sequence[object]) -> int:
    """Hash of an attribute record (``kind`` names the table, ``key`` the element): of
    ``f"a{kind}:{key joined by commas}:{attribute_text(values)}"``."""
    return _hash(f"a{kind}:{','.join(map(str, key))}:{attribute_text(values)}".encode())


def attribute_text(values: Sequence[object]) -> str:
    """The values' part of :func:`attribute_hash`'s text (a kernel hashing many elements
    with the same values computes it once)."""
    return ",".join(_rational_text(v) if hasattr(v, "denominator") else str(v)
                    for v in values)


def combine(digest: int, element: int) -> int:
    """Digest after adding an element with hash ``element``."""
    return (digest + element) & _MASK


def remove(digest: int, element: int) -> int:
    """Digest after removing an element with hash ``element``."""
    return (digest - element) & _MASK


def digest_text(digest: int) -> str:
    """The 32-hex-digit form used in traces and reports."""
    return f"{digest:032x}"
