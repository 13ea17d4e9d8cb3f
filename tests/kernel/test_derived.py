"""``kernel.derived.Derived``: the one mechanism by which a frozen snapshot defers work
(issue 25, item 3) -- each value made once, kept, never replaced; safe from two threads;
a snapshot's fields never change after construction."""

from __future__ import annotations

import pickle
import threading

import attrs

from geomexact import mpq
from geomexact.kernel.derived import Derived
from geomexact.mesh2d.refinement.api import refine
from geomexact.mesh2d.refinement.criteria import MaxArea
from geomexact.mesh2d.refinement.engines import compiled
from geomexact.mesh2d.transient import mesh_from_triangles


def test_a_value_is_made_once_and_kept() -> None:
    derived, calls = Derived(), []
    assert derived.get("x", lambda: calls.append(1) or 5) == 5
    assert derived.get("x", lambda: calls.append(1) or 6) == 5
    assert calls == [1] and derived.known("x") and not derived.known("y")


def test_a_make_may_read_another_value() -> None:
    derived = Derived()
    assert derived.get("b", lambda: derived.get("a", lambda: 2) + 1) == 3


def test_two_threads_make_it_once() -> None:
    derived, calls = Derived(), []
    barrier = threading.Barrier(8)

    def make() -> int:
        calls.append(1)
        return len(calls)

    def read(results: list[int]) -> None:
        barrier.wait()
        results.append(derived.get("v", make))

    results: list[int] = []
    threads = [threading.Thread(target=read, args=(results,)) for _ in range(8)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert calls == [1] and results == [1] * 8


def test_it_pickles_with_its_values() -> None:
    derived = Derived()
    derived.get("x", lambda: (1, 2))
    copy = pickle.loads(pickle.dumps(derived))
    assert copy.get("x", lambda: None) == (1, 2)


def test_a_snapshot_from_a_kernel_keeps_its_fields_and_builds_its_tables_once() -> None:
    """A refined mesh (the kernel's arrays, or tables) reads the same before and after its
    tables are built; its fields are the same objects; evolve never shares the tables; a
    refinement of it with the default budget builds none of them."""
    square = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)])
    mesh = refine(square, MaxArea(mpq(1, 200))).mesh
    fields = attrs.asdict(mesh, recurse=False)
    had_source = mesh.source is not None  # the compiled kernel's result: arrays
    assert had_source or not compiled.AVAILABLE
    again = refine(mesh, MaxArea(mpq(1, 400))).mesh
    assert again.triangle_count > mesh.triangle_count
    assert (mesh.source is not None) == had_source  # the budget built no table
    first = mesh.halfedges
    assert mesh.halfedges is first and mesh.source is None
    assert attrs.asdict(mesh, recurse=False).keys() == fields.keys()
    assert all(attrs.asdict(mesh, recurse=False)[key] is value
               for key, value in fields.items() if key != "_derived")
    assert attrs.evolve(mesh).halfedges == first
