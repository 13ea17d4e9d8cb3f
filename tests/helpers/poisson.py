"""A P1 finite-element Poisson solve with scikit-fem on a geomexact tetrahedral mesh, for
the tests that show meshes are usable: the manufactured solution u = sin x cos y e^z
(-Δu = u), Dirichlet data at the boundary vertices; the L2 error of the solution."""

from __future__ import annotations

import numpy as np
import pytest

from geomexact.mesh3d.snapshot import Mesh3


def exact_solution(x: np.ndarray) -> np.ndarray:
    return np.sin(x[0]) * np.cos(x[1]) * np.exp(x[2])  # type: ignore[no-any-return]


def p1_l2_error(mesh: Mesh3) -> float:
    """The L2 error of the P1 solution on ``mesh`` (skips without scikit-fem)."""
    skfem = pytest.importorskip("skfem")
    from skfem.helpers import dot, grad

    laplace = skfem.BilinearForm(lambda u, v, w: dot(grad(u), grad(v)))
    load = skfem.LinearForm(lambda v, w: exact_solution(w.x) * v)
    error = skfem.Functional(lambda w: (w["uh"] - exact_solution(w.x)) ** 2)
    points = np.array([[p.fx, p.fy, p.fz] for p in mesh.point_list()]).T
    fem = skfem.MeshTet(points, np.ascontiguousarray(np.array(mesh.tetrahedra()).T))
    basis = skfem.Basis(fem, skfem.ElementTetP1())
    boundary = fem.boundary_nodes()
    values = np.zeros(basis.N)
    values[boundary] = exact_solution(points[:, boundary])
    u = skfem.solve(*skfem.condense(laplace.assemble(basis), load.assemble(basis), x=values,
                                    D=boundary))
    return float(np.sqrt(error.assemble(basis, uh=basis.interpolate(u))))


def rates(sizes: list[float], errors: list[float]) -> list[float]:
    """The convergence rates between successive sizes."""
    return [float(np.log(errors[i - 1] / errors[i]) / np.log(sizes[i - 1] / sizes[i]))
            for i in range(1, len(errors))]
