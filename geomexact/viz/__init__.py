"""Pictures and the offline HTML viewer.

- :func:`plot` / :func:`plot_step`: PNG, SVG or PDF pictures with matplotlib (the
  ``pictures`` extra) of a mesh, a PSLG, a polygon mesh; the mesh after one step of a
  trace with that step highlighted;
- :func:`viewer_html` / :func:`write_viewer`: one self-contained HTML file (JavaScript and
  CSS inline, no network request at any time) with pan and zoom, statistics, hover
  details, a file-open control and, for a trace, a step slider;
- :func:`viewer_html_3d` / :func:`write_viewer_3d`: the same for a tetrahedral mesh
  (``Mesh3``) or a mixed-cell mesh (``MixedMesh3``, faces drawn as their polygons):
  rotate, zoom, shrink cells, a clip plane, colour by radius ratio, cell kind or creating
  step, boundary faces or all, a step slider over a trace;
- :func:`plot_mesh3` / :func:`figure_mesh3`: pictures of a tetrahedral or mixed-cell mesh
  (its visible surface, optionally cut open by a :func:`clip_plane`, coloured by radius
  ratio or cell kind).

The local server that shows a directory in the viewer is :mod:`geomexact.server`.  Names
load on first use (matplotlib only with the pictures).  Guide: ``docs/viewer.md``; payload
format: ``specs/viewer.md``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from geomexact._lazy_exports import lazy_exports

if TYPE_CHECKING:
    from geomexact.viz.pictures import figure, plot, plot_step
    from geomexact.viz.pictures3d import figure_mesh3, plot_mesh3
    from geomexact.viz.scene import CellChanges, History, Scene, history_of, scene_of
    from geomexact.viz.scene3d import clip_plane, viewer_html_3d, write_viewer_3d
    from geomexact.viz.viewer import Download, empty_viewer_html, viewer_html, write_viewer

_HOMES: dict[str, str] = {
    "figure": "geomexact.viz.pictures",
    "plot": "geomexact.viz.pictures",
    "plot_step": "geomexact.viz.pictures",
    "figure_mesh3": "geomexact.viz.pictures3d",
    "plot_mesh3": "geomexact.viz.pictures3d",
    "clip_plane": "geomexact.viz.scene3d",
    "CellChanges": "geomexact.viz.scene",
    "History": "geomexact.viz.scene",
    "Scene": "geomexact.viz.scene",
    "history_of": "geomexact.viz.scene",
    "scene_of": "geomexact.viz.scene",
    "Download": "geomexact.viz.viewer",
    "empty_viewer_html": "geomexact.viz.viewer",
    "viewer_html": "geomexact.viz.viewer",
    "write_viewer": "geomexact.viz.viewer",
    "viewer_html_3d": "geomexact.viz.scene3d",
    "write_viewer_3d": "geomexact.viz.scene3d",
}

__all__ = [
    "CellChanges",
    "Download",
    "History",
    "Scene",
    "clip_plane",
    "empty_viewer_html",
    "figure",
    "figure_mesh3",
    "history_of",
    "plot",
    "plot_mesh3",
    "plot_step",
    "scene_of",
    "viewer_html",
    "viewer_html_3d",
    "write_viewer",
    "write_viewer_3d",
]

__getattr__, __dir__ = lazy_exports(__name__, globals(), _HOMES)
