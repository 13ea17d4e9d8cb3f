"""Content digests (``geomexact.kernel.digest``): each element hash follows the encoding of
``specs/snapshot.md`` (recomputed here independently), the digest is a sum mod 2^128 (order
independent, incremental add/remove equal to a full recomputation), and it does not depend
on the process hash seed."""

from __future__ import annotations

import contextlib
import io
import os
import struct
import subprocess
import sys
from hashlib import blake2b

import gmpy2
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact.kernel import digest
from geomexact.kernel.numbers import mpq
from geomexact.kernel.points import point2
from geomexact.mesh2d.snapshot import Mesh2, full_digest
from geomexact.mesh2d.transient import Transient2, mesh_from_triangles
from geomexact.strategies import coordinates, rationals, triangulations

FEW = settings(max_examples=min(settings().max_examples, 40))
MASK = (1 << 128) - 1
hashes = st.integers(0, MASK)


# -- independent implementations of the spec's encodings -------------------------------------
def spec_blake(payload: bytes, person: bytes = b"") -> int:
    return int.from_bytes(blake2b(payload, digest_size=16, person=person).digest(), "little")


def spec_vertex_hash(vertex: int, coordinates: tuple[mpq, ...]) -> int:
    payload = struct.pack("<Q", vertex) + b"".join(gmpy2.to_binary(c) for c in coordinates)
    return spec_blake(payload, b"vertex")


def spec_key(vertex: int) -> int:
    raw = blake2b(struct.pack("<Q", vertex), digest_size=8, person=b"vkey").digest()
    return int.from_bytes(raw, "little")


def spec_cell_hash(cell: tuple[int, ...]) -> int:
    x = sum(spec_key(v) * m for v, m in zip(cell, digest._POSITION_MULTIPLIERS, strict=False))
    x %= 1 << 128
    x ^= x >> 61
    return (x * digest.FINAL_MULTIPLIER) % (1 << 128)


def spec_mesh_digest(mesh: Mesh2) -> int:
    """The digest of ``mesh`` from the element table of ``specs/snapshot.md``."""
    total = 0
    for vertex, p in mesh.vertices.items():
        total += spec_vertex_hash(vertex, (p.x, p.y))
    for triangle in mesh.triangles():
        total += spec_cell_hash(triangle)
    for (u, v), marker in mesh.segments.items():
        total += spec_blake(f"s{u},{v}:{marker}".encode())
    for vertex, marker in mesh.vertex_markers.items():
        total += spec_blake(f"avm:{vertex}:{marker}/1".encode())
    return total % (1 << 128)


# -- the arithmetic --------------------------------------------------------------------------
def test_the_modulus_is_two_to_the_128() -> None:
    """Digests live in Z / 2^128."""
    assert digest.MODULUS == 1 << 128
    assert digest.combine(MASK, 1) == 0
    assert digest.remove(0, 1) == MASK


@given(hashes, hashes)
def test_remove_undoes_combine(total: int, element: int) -> None:
    """Removing an element that was added restores the digest, in either order."""
    assert digest.remove(digest.combine(total, element), element) == total
    assert digest.combine(digest.remove(total, element), element) == total
    assert 0 <= digest.combine(total, element) <= MASK


@FEW
@given(st.lists(hashes, max_size=30), st.randoms(use_true_random=False))
def test_the_digest_of_a_set_does_not_depend_on_the_order(
    elements: list[int], random: object
) -> None:
    """Combining the same element hashes in any order gives the same digest: their sum mod
    2^128."""
    forward = 0
    for element in elements:
        forward = digest.combine(forward, element)
    shuffled = list(elements)
    random.shuffle(shuffled)  # type: ignore[attr-defined]
    backward = 0
    for element in shuffled:
        backward = digest.combine(backward, element)
    assert forward == backward == sum(elements) % (1 << 128)


def test_digest_text_is_32_lowercase_hex_digits() -> None:
    """digest_text pads with zeros to 32 digits and reads back to the same integer."""
    assert digest.digest_text(0) == "0" * 32
    assert digest.digest_text(255) == "0" * 30 + "ff"
    assert digest.digest_text(MASK) == "f" * 32
    value = 0x0123456789ABCDEF0123456789ABCDEF
    assert digest.digest_text(value) == "0123456789abcdef0123456789abcdef"
    assert int(digest.digest_text(value), 16) == value


# -- element hashes ---------------------------------------------------------------------------
@FEW
@given(st.integers(0, 2**40), coordinates(), coordinates())
def test_vertex_hash_follows_the_spec(vertex: int, x: mpq, y: mpq) -> None:
    """BLAKE2b-128 personalised ``vertex`` of the id (u64 LE) then gmpy2.to_binary of each
    exact coordinate, read little endian."""
    assert digest.vertex_hash(vertex, (x, y)) == spec_vertex_hash(vertex, (x, y))


def test_vertex_hash_depends_on_the_exact_value_only() -> None:
    """Equal rationals hash alike however written; a different id, a tiny change of a
    coordinate or swapped coordinates change the hash; 3D coordinates are hashed too."""
    base = digest.vertex_hash(3, (mpq(1, 2), mpq(1, 3)))
    assert digest.vertex_hash(3, (mpq(2, 4), mpq(3, 9))) == base
    assert digest.vertex_hash(3, point2("0.5", mpq(1, 3))[:2]) == base
    assert digest.vertex_hash(4, (mpq(1, 2), mpq(1, 3))) != base
    assert digest.vertex_hash(3, (mpq(1, 2) + mpq(1, 2**300), mpq(1, 3))) != base
    assert digest.vertex_hash(3, (mpq(1, 3), mpq(1, 2))) != base
    spatial = digest.vertex_hash(3, (mpq(1, 2), mpq(1, 3), mpq(0)))
    assert spatial != base and spatial == spec_vertex_hash(3, (mpq(1, 2), mpq(1, 3), mpq(0)))


@FEW
@given(st.integers(0, 5000))
def test_vertex_key_follows_the_spec(vertex: int) -> None:
    """The key of a vertex is the first 8 bytes (LE) of BLAKE2b personalised ``vkey`` of
    its id, and the cache holds exactly those keys for ids 0..n-1."""
    assert digest.vertex_key(vertex) == spec_key(vertex)
    keys = digest.VERTEX_KEYS
    assert len(keys) > vertex
    assert all(keys[i] == spec_key(i) for i in (0, vertex // 2, vertex))


@FEW
@given(st.lists(st.integers(0, 3000), min_size=3, max_size=3, unique=True))
def test_triangle_cell_hash_follows_the_spec(cell: list[int]) -> None:
    """x = Σ key(id_i)·M_i mod 2^128, x ^= x >> 61, h = x·M_f mod 2^128, with the cache
    filled on demand."""
    assert digest.cell_hash(tuple(cell)) == spec_cell_hash(tuple(cell))
    assert digest._POSITION_MULTIPLIERS[:3] == digest.TRIANGLE_MULTIPLIERS


@FEW
@given(st.lists(st.integers(0, 3000), min_size=4, max_size=4, unique=True))
def test_tetrahedron_cell_hash_follows_the_spec(cell: list[int]) -> None:
    """Tetrahedra use the same formula with the four position multipliers."""
    assert digest.cell_hash(tuple(cell)) == spec_cell_hash(tuple(cell))


def test_cell_hash_of_a_vertex_beyond_the_cache() -> None:
    """A cell with an id never seen before extends the key cache and hashes as specified."""
    high = len(digest.VERTEX_KEYS) + 777
    cell = (0, high - 1, high)
    assert digest.cell_hash(cell) == spec_cell_hash(cell)
    assert len(digest.VERTEX_KEYS) == high + 1


def test_cell_hash_distinguishes_orientation_and_vertices() -> None:
    """(0, 1, 2) and (0, 2, 1) are different triangles; so are triangles on other ids."""
    assert digest.cell_hash((0, 1, 2)) != digest.cell_hash((0, 2, 1))
    assert digest.cell_hash((0, 1, 2)) != digest.cell_hash((0, 1, 3))
    assert digest.cell_hash((0, 1, 2, 3)) != digest.cell_hash((0, 1, 3, 2))


def test_all_multipliers_are_odd_128_bit_constants() -> None:
    """Odd multipliers are invertible mod 2^128 (no information is thrown away)."""
    for m in (*digest._POSITION_MULTIPLIERS, digest.FINAL_MULTIPLIER):
        assert m % 2 == 1 and m.bit_length() <= 128 and m.bit_length() > 64


def test_segment_hash_follows_the_spec() -> None:
    """BLAKE2b-128 of ``s{u},{v}:{marker}``; the marker matters."""
    assert digest.segment_hash(2, 7, 1) == spec_blake(b"s2,7:1")
    assert digest.segment_hash(2, 7, 0) == spec_blake(b"s2,7:0")
    assert digest.segment_hash(2, 7, 0) != digest.segment_hash(2, 7, 1)
    assert digest.segment_hash(2, 7, -3) == spec_blake(b"s2,7:-3")


def test_attribute_hashes_of_rational_values_follow_the_spec() -> None:
    """Vertex and triangle attributes hash ``a{kind}:{ids}:{p/q,...}``."""
    values = (mpq(1, 2), mpq(-3), mpq(0))
    assert digest.attribute_hash("va", (4,), values) == spec_blake(b"ava:4:1/2,-3/1,0/1")
    assert digest.attribute_hash("ta", (1, 5, 2), values) == spec_blake(
        b"ata:1,5,2:1/2,-3/1,0/1"
    )
    assert digest.attribute_hash("va", (4,), (mpq(2, 4),)) == digest.attribute_hash(
        "va", (4,), (mpq(1, 2),)
    )
    assert digest.attribute_hash("va", (4,), values) != digest.attribute_hash("ta", (4,), values)


def test_vertex_marker_hash_follows_the_spec() -> None:
    """A vertex marker m of vertex i hashes BLAKE2b-128 of ``avm:{i}:{m}/1`` (the spec
    was corrected to the encoding every recorded digest uses)."""
    assert digest.attribute_hash("vm", (3,), (5,)) == spec_blake(b"avm:3:5/1")


# -- digests of meshes ------------------------------------------------------------------------
@FEW
@given(triangulations(max_steps=12))
def test_mesh_digest_equals_the_spec_sum_of_its_elements(mesh: Mesh2) -> None:
    """A mesh's incremental digest equals the sum of its element hashes computed from the
    spec (vertices, triangles, segments; markers as the module hashes them)."""
    assert not mesh.vertex_attributes
    assert not mesh.triangle_attributes
    assert mesh.digest == spec_mesh_digest(mesh) == full_digest(mesh)


def test_the_digest_depends_on_content_not_on_insertion_order() -> None:
    """The same triangles and segments given in another order, or rotated, give the same
    digest."""
    points = [(0, 0), (2, 0), (2, 2), (0, 2), (1, 1)]
    triangles = [(0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)]
    segments = [(0, 1, 1), (1, 2, 2), (2, 3, 3), (3, 0, 4)]
    first = mesh_from_triangles(points, triangles, segments)
    rotated = [(t[1], t[2], t[0]) for t in reversed(triangles)]
    second = mesh_from_triangles(points, rotated, list(reversed(segments)))
    assert first.digest == second.digest
    relabelled = mesh_from_triangles(points, triangles, [(1, 0, 1), *segments[1:]])
    assert relabelled.digest == first.digest


def _random_edits(t: Transient2, data: st.DataObject) -> None:
    """Random low-level edits of every kind that the digest tracks."""
    for _ in range(data.draw(st.integers(1, 12))):
        kind = data.draw(st.sampled_from(
            ["vertex", "marker", "remove", "readd", "segment", "unsegment", "attributes"]))
        triangles = sorted(
            (u, v, w) for (u, v), w in t.halfedges_snapshot().items() if u < v and u < w)
        if kind == "vertex":
            t.add_vertex(point2(data.draw(rationals()), data.draw(rationals())),
                         data.draw(st.integers(0, 3)),
                         tuple(data.draw(st.lists(rationals(), max_size=2))))
        elif kind == "marker":
            t.set_vertex_marker(data.draw(st.integers(0, t.vertex_count - 1)),
                                data.draw(st.integers(0, 3)))
        elif kind in ("remove", "readd", "attributes") and triangles:
            triangle = data.draw(st.sampled_from(triangles))
            if kind == "attributes":
                values = tuple(data.draw(st.lists(rationals(), max_size=2)))
                t.set_triangle_attributes(triangle, values)
            else:
                t.remove_triangle(*triangle)
                if kind == "readd":
                    t.add_triangle(*triangle)
        elif kind == "segment":
            u, v = data.draw(st.lists(st.integers(0, t.vertex_count - 1), min_size=2,
                                      max_size=2, unique=True))
            t.set_segment(u, v, data.draw(st.integers(0, 3)))
        elif kind == "unsegment":
            segments = sorted({(u, v) for u, v, _ in _segments(t)})
            if segments:
                t.remove_segment(*data.draw(st.sampled_from(segments)))


def _segments(t: Transient2) -> list[tuple[int, int, int]]:
    return [
        (u, v, marker)
        for u in range(t.vertex_count)
        for v in range(u + 1, t.vertex_count)
        if (marker := t.segment_marker(u, v)) is not None
    ]


@FEW
@given(triangulations(max_steps=8), st.data())
def test_incremental_updates_equal_a_full_recomputation(mesh: Mesh2, data: st.DataObject) -> None:
    """After any sequence of adds and removes of vertices, markers, attributes, triangles
    and segments, the running digest equals the digest recomputed from the content."""
    t = Transient2(mesh)
    _random_edits(t, data)
    running = t.digest
    sealed = t.seal()
    assert sealed.digest == running == full_digest(sealed)


@FEW
@given(triangulations(max_steps=8))
def test_removing_everything_gives_the_digest_of_the_vertices(mesh: Mesh2) -> None:
    """Removing every triangle and segment leaves exactly the sum of the vertex hashes
    (with their markers)."""
    t = Transient2(mesh)
    for triangle in mesh.triangles():
        t.remove_triangle(*triangle)
    for u, v, _ in mesh.segment_list():
        t.remove_segment(u, v)
    expected = sum(
        spec_vertex_hash(i, (p.x, p.y)) for i, p in mesh.vertices.items())
    expected += sum(
        digest.attribute_hash("vm", (i,), (m,)) for i, m in mesh.vertex_markers.items())
    expected %= 1 << 128
    assert t.digest == expected


_SEED_WORKLOAD = """
import sys
from geomexact.kernel import digest
from geomexact.kernel.numbers import mpq
from geomexact.mesh2d.transient import mesh_from_triangles
mesh = mesh_from_triangles(
    [(0, 0), ("0.1", 0), (mpq(1, 3), "2.5"), (0, 1)],
    [(0, 1, 2), (0, 2, 3)],
    [(0, 1, 1), (2, 3, 2)],
    vertex_markers=[0, 1, 0, 2],
    vertex_attributes=[(), (mpq(1, 7),), (), ()],
    triangle_attributes=[(mpq(5),), ()],
)
values = [
    mesh.digest,
    digest.cell_hash((4, 9, 1, 7)),
    digest.segment_hash(1, 2, 3),
    digest.attribute_hash("ta", (0, 1, 2), (mpq(1, 2),)),
    digest.vertex_hash(5, (mpq(1, 3), mpq(-2), mpq(7, 9))),
]
sys.stdout.write(" ".join(digest.digest_text(v) for v in values))
"""


def test_digests_do_not_depend_on_the_hash_seed() -> None:
    """The same mesh and element hashes, computed in processes with different
    PYTHONHASHSEED, give identical digests (and the same as this process)."""
    outputs = []
    for seed in ("0", "31337"):
        result = subprocess.run(
            [sys.executable, "-c", _SEED_WORKLOAD],
            capture_output=True,
            env={**os.environ, "PYTHONHASHSEED": seed},
            check=True,
        )
        outputs.append(result.stdout.decode())
    here = io.StringIO()
    with contextlib.redirect_stdout(here):
        exec(_SEED_WORKLOAD, {})
    assert outputs[0] == outputs[1] == here.getvalue()
    assert len(outputs[0].split()) == 5
