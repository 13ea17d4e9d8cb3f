"""The public facade: every name in ``geomexact.__all__`` resolves, and the documented
entry points are importable from the top level."""

from __future__ import annotations

import importlib

import geomexact


def test_every_name_in_all_resolves() -> None:
    for name in geomexact.__all__:
        assert hasattr(geomexact, name), name


def test_all_has_no_duplicates_and_is_sorted_like_ruff_wants() -> None:
    assert len(set(geomexact.__all__)) == len(geomexact.__all__)


def test_submodules_named_in_docs_import() -> None:
    for module in ("kernel.numbers", "kernel.predicates2d", "kernel.predicates3d",
                   "mesh2d.snapshot", "mesh2d.transient", "mesh2d.ops", "trace.record", "io",
                   "mesh2d.delaunay.triangulation", "mesh2d.validation", "strategies",
                   "mesh2d.segments", "kernel.collector"):
        importlib.import_module(f"geomexact.{module}")
