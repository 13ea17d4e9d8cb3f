"""The 3D API is importable from one place, like the 2D one (issue 26, item 7): each name
resolves to the object its home module defines, loaded on first use."""

from __future__ import annotations

import importlib

import geomexact

THREE_D = ("Mesh3", "Transient3", "mesh3_from_tetrahedra", "validate3", "MixedMesh3",
           "validate_mixed", "Box", "Octree", "generate", "generate_cells", "generate_domain",
           "generate_device", "RefineWhere", "BoxGrid", "DerefineWhere", "MixedPartition",
           "PolyhedralPartition", "TriangleSurface", "triangle_surface", "check_surface",
           "oriented_outward", "read_surface", "control_volumes", "improve_quality",
           "QualityCriterion", "to_arrays", "from_arrays", "triangulate_arrays")


def test_the_3d_names_resolve_from_the_package() -> None:
    for name in THREE_D:
        assert name in geomexact.__all__, name
        value = getattr(geomexact, name)
        home = importlib.import_module(value.__module__)
        assert getattr(home, name) is value, name


def test_a_box_mesh_from_the_facade() -> None:
    run = geomexact.generate(geomexact.Box((0, 0, 0), (1, 1, 1)),
                             refinement=geomexact.RefineWhere(1), trace=False)
    assert isinstance(run.mesh, geomexact.Mesh3) and geomexact.validate3(run.mesh) == []
