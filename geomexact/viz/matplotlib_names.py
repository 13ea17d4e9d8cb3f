"""The matplotlib names the picture modules draw with, imported in one place: without
matplotlib (the ``pictures`` extra), importing any picture module raises
:class:`~geomexact.errors.MissingDependencyError` naming that extra."""

from __future__ import annotations

from geomexact.errors import MissingDependencyError

try:
    from matplotlib import colormaps, rc_context
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.cm import ScalarMappable
    from matplotlib.collections import LineCollection, PolyCollection
    from matplotlib.colors import BoundaryNorm, ListedColormap, LogNorm, Normalize, to_rgb
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch
except ImportError as error:
    raise MissingDependencyError("matplotlib", "pictures", "pictures") from error

__all__ = [
    "BoundaryNorm",
    "Figure",
    "FigureCanvasAgg",
    "LineCollection",
    "ListedColormap",
    "LogNorm",
    "Normalize",
    "Patch",
    "PolyCollection",
    "ScalarMappable",
    "colormaps",
    "rc_context",
    "to_rgb",
]
