"""Pictures and the offline HTML viewer.

- :func:`plot` / :func:`plot_step`: PNG, SVG or PDF pictures with matplotlib (a mesh, a
  PSLG, a polygon mesh; the mesh after one step of a trace with that step highlighted);
- :func:`viewer_html` / :func:`write_viewer`: one self-contained HTML file (JavaScript and
  CSS inline, no network request at any time) with pan and zoom, statistics, hover
  details, a file-open control and, for a trace, a step slider;
- :mod:`geomexact.server`: ``geomexact serve``, a local HTTP server that lists mesh
  files, opens them in the viewer and refines uploaded ones.

Guide: ``docs/viewer.md``; payload format: ``specs/viewer.md``.
"""

from __future__ import annotations

from geomexact.viz.pictures import figure, plot, plot_step
from geomexact.viz.scene import History, Scene, history_of, scene_of
from geomexact.viz.viewer import Download, empty_viewer_html, viewer_html, write_viewer

__all__ = [
    "Download",
    "History",
    "Scene",
    "empty_viewer_html",
    "figure",
    "history_of",
    "plot",
    "plot_step",
    "scene_of",
    "viewer_html",
    "write_viewer",
]
