"""The self-contained HTML viewer: one file with the mesh, its trace and the viewer's
JavaScript and CSS inline, which makes no network request at any time.

The page's data is a JSON payload (``"format": "geomexact-view"``, version 1) in a
``<script type="application/json">`` element; arrays of numbers travel as base64 of
little-endian typed arrays (``Float64Array`` coordinates, ``Uint32Array`` ids).  With a
trace the payload carries a :class:`~geomexact.viz.scene.History`: the triangles each step
added and removed, so the page steps through a long run by touching only what changed.
A Content-Security-Policy forbids every fetch, connection, frame, font and image that is
not inline.  Specification: ``specs/viewer.md``.
"""

from __future__ import annotations

import base64
import html
import json
import re
from array import array
from collections.abc import Sequence
from importlib import resources
from pathlib import Path
from typing import Any

import attrs

from geomexact.io.files import write_text_atomic
from geomexact.trace.record import Trace
from geomexact.viz.scene import (
    DEFAULT_EXACT_BUDGET,
    CellChanges,
    History,
    Scene,
    Viewable,
    history_of,
    little_endian,
    scene_of,
    trace_start,
)

PAYLOAD_FORMAT = "geomexact-view"
PAYLOAD_VERSION = 1

VIEWER_CSP = (
    "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; "
    "img-src data: blob:; base-uri 'none'; form-action 'none'"
)
"""The page's Content-Security-Policy: inline script and style only, nothing fetched."""

FILL_MODES = ("none", "min_angle", "area", "region")
"""How the page fills faces: plainly, by smallest angle, by area, by region attribute."""


@attrs.frozen
class Download:
    """A file the page offers to save (from memory: a ``blob:`` URL, no request)."""

    name: str
    text: str


def _b64(values: array[Any] | None) -> str | None:
    if values is None:
        return None
    return base64.b64encode(little_endian(values)).decode("ascii")


def scene_payload(scene: Scene, *, with_cells: bool = True) -> dict[str, Any]:
    """The ``scene`` object of the payload (``with_cells=False`` leaves the triangles and
    segments to the history)."""
    return {
        "kind": scene.kind,
        "dimension": scene.dimension,
        "vertex_count": scene.vertex_count,
        "xy": _b64(scene.xy),
        "exact": list(scene.exact) if scene.exact is not None else None,
        "triangles": _b64(scene.triangles) if with_cells else "",
        "regions": _b64(scene.regions),
        "polygon_offsets": _b64(scene.polygon_offsets),
        "polygon_vertices": _b64(scene.polygon_vertices),
        "nonconvex": _b64(scene.nonconvex),
        "segments": _b64(scene.segments) if with_cells else "",
        "holes": _b64(scene.holes),
        "seeds": _b64(scene.seeds),
        "summary": scene.summary,
        "scale_exponent": scene.scale_exponent,
    }


def _scale_notes(scene: Scene) -> list[str]:
    if not scene.scale_exponent:
        return []
    return [f"coordinates drawn × 2^{-scene.scale_exponent} (exactly; they are beyond the "
            "comfortable range of doubles): drawn measures are scaled, the exact ones are "
            "not"]


def _changes_payload(prefix: str, changes: CellChanges) -> dict[str, str | None]:
    return {
        f"{prefix}cells": _b64(changes.cells),
        f"{prefix}start": _b64(changes.start),
        f"{prefix}added_offsets": _b64(changes.added_offsets),
        f"{prefix}added": _b64(changes.added),
        f"{prefix}removed_offsets": _b64(changes.removed_offsets),
        f"{prefix}removed": _b64(changes.removed),
    }


def history_payload(history: History) -> dict[str, Any]:
    """The ``history`` object of the payload."""
    return {
        "steps": history.steps,
        "labels": list(history.labels),
        **_changes_payload("", history.triangles),
        **_changes_payload("segment_", history.segments),
        "vertex_counts": _b64(history.vertex_counts),
        "input_digest": history.input_digest,
        "final_digest": history.final_digest,
    }


def payload(
    scene: Scene,
    history: History | None = None,
    *,
    title: str = "",
    source: str | None = None,
    trace_source: str | None = None,
    notes: Sequence[str] = (),
    download: Download | None = None,
    fill: str = "none",
    step: int | None = None,
) -> dict[str, Any]:
    """The whole JSON payload of a page; ``fill`` and ``step`` are the page's initial fill
    mode and step."""
    from geomexact._version import __version__

    return {
        "format": PAYLOAD_FORMAT,
        "version": PAYLOAD_VERSION,
        "generator": f"geomexact {__version__}",
        "title": title,
        "source": {"file": source, "trace": trace_source},
        "notes": list(notes) + _scale_notes(scene),
        "scene": scene_payload(scene, with_cells=history is None),
        "history": history_payload(history) if history is not None else None,
        "download": attrs.asdict(download) if download is not None else None,
        "options": {"fill": fill, "step": step},
    }


def page_asset(name: str) -> str:
    """The text of one of the viewer's files (``viewer.js``, ``viewer.css``, …)."""
    return (resources.files("geomexact.viz") / name).read_text(encoding="utf-8")


def _check_inline(name: str, text: str) -> str:
    lowered = text.lower()
    for bad in ("</script", "</style", "<!--"):
        if bad in lowered:
            raise ValueError(f"{name} contains {bad!r}, which would end its inline element")
    return text


def _links_html(links: Sequence[tuple[str, str]]) -> str:
    if not links:
        return ""
    items = " ".join(
        f'<a href="{html.escape(href, quote=True)}">{html.escape(label)}</a>'
        for label, href in links
    )
    return f"<nav>{items}</nav>"


_PLACEHOLDER = re.compile(r"\{\{(\w+)\}\}")

PAGE_HEAD = "page_head.html"
"""The start the 2D and 3D pages share (the doctype, the opening tags and the ``<head>``),
put in place of ``{{head}}``."""

STEP_CONTROLS = "step_controls.html"
"""The trace panel the 2D and 3D pages share (slider, buttons, go to step, op filter), put
in place of ``{{step_controls}}``; its script is :data:`STEP_CONTROLS_JS`."""

STEP_CONTROLS_JS = "step_controls.js"
"""The script of :data:`STEP_CONTROLS`, inlined before each page's own script."""

PAGE_END = "page_end.html"
"""The end the 2D and 3D pages share (the payload and the script elements, the closing
tags), put in place of ``{{end}}``."""

_INCLUDES = {"head": PAGE_HEAD, "step_controls": STEP_CONTROLS, "end": PAGE_END}


def fill_page(template: str, values: dict[str, str]) -> str:
    """The page ``template`` (a viewer file whose ``{{head}}``, ``{{step_controls}}`` and
    ``{{end}}`` are replaced by :data:`PAGE_HEAD`, :data:`STEP_CONTROLS` and
    :data:`PAGE_END` first) with each
    ``{{name}}`` replaced by ``values[name]`` in one pass, so no value can bring in another
    placeholder."""
    text = page_asset(template)
    for name, asset in _INCLUDES.items():
        text = text.replace("{{" + name + "}}", page_asset(asset).rstrip("\n"), 1)
    return _PLACEHOLDER.sub(lambda match: values[match.group(1)], text)


def page_script(name: str) -> str:
    """The inline script of a page: :data:`STEP_CONTROLS_JS`, then the page's own ``name``
    (each checked by :func:`_check_inline`)."""
    return (_check_inline(STEP_CONTROLS_JS, page_asset(STEP_CONTROLS_JS)) + "\n"
            + _check_inline(name, page_asset(name)))


def page_css() -> str:
    """The inline style sheet of the 2D and 3D pages (checked by :func:`_check_inline`)."""
    return _check_inline("viewer.css", page_asset("viewer.css"))


def payload_json(data: dict[str, Any]) -> str:
    """A page's payload as the text of its JSON script element: compact, keys sorted."""
    text = json.dumps(data, sort_keys=True, separators=(",", ":"), allow_nan=False)
    # "<" only occurs inside JSON strings, where \u003c is the same character; so
    # nothing in the payload can close the script element
    return text.replace("<", "\\u003c")


def render_page(data: dict[str, Any] | None, *, title: str,
                links: Sequence[tuple[str, str]] = ()) -> str:
    """The HTML page for a payload (None: an empty viewer that opens files)."""
    from geomexact._version import __version__

    values = {
        "csp": VIEWER_CSP,
        "generator": f"geomexact {__version__}",
        "title": html.escape(title or "geomexact viewer"),
        "links": _links_html(links),
        "css": page_css(),
        "js": page_script("viewer.js"),
        "data": "" if data is None else payload_json(data),
    }
    return fill_page("viewer.html", values)


def viewer_html(
    value: Viewable,
    *,
    trace: Trace | None = None,
    title: str | None = None,
    source: str | None = None,
    trace_source: str | None = None,
    exact_budget: int = DEFAULT_EXACT_BUDGET,
    notes: Sequence[str] = (),
    links: Sequence[tuple[str, str]] = (),
    download: Download | None = None,
    fill: str = "none",
    step: int | None = None,
    summary: bool = True,
) -> str:
    """The self-contained viewer page of a mesh, PSLG or polygon mesh.

    With ``trace``, ``value`` is the trace's input (a mesh, or the PSLG a triangulation
    started from): the trace is replayed once, every digest checked
    (:class:`~geomexact.errors.TraceError` otherwise), and the page shows the result with
    a step slider over every intermediate mesh.  ``exact_budget`` caps the characters of
    exact coordinate text embedded for the hover panel (0: none).  ``links`` are (label,
    URL) pairs shown in the header (the server's navigation); ``download`` a file the page
    offers to save.  ``fill`` is the initial fill (``"none"``, ``"min_angle"``, ``"area"``,
    ``"region"``); ``step`` the step first shown (default: the last); ``summary=False``
    skips the exact statistics (total area, Delaunay test), which cost O(n) exact
    predicates.  O(n + total changes of the trace); the output is byte-identical for equal
    inputs.
    """
    if fill not in FILL_MODES:
        raise ValueError(f"fill must be one of {', '.join(FILL_MODES)}, not {fill!r}")
    history = None
    if trace is not None:
        history = history_of(trace_start(value), trace)
        if step is not None and not 0 <= step <= history.steps:
            raise ValueError(f"step {step} is outside 0..{history.steps}")
        scene = scene_of(history.final, exact_budget=exact_budget, summary=summary)
    else:
        scene = scene_of(value, exact_budget=exact_budget, summary=summary)
    shown = title or source or "mesh"
    data = payload(scene, history, title=shown, source=source, trace_source=trace_source,
                   notes=notes, download=download, fill=fill,
                   step=step if history is not None else None)
    return render_page(data, title=shown, links=links)


def empty_viewer_html(*, title: str = "geomexact viewer",
                      links: Sequence[tuple[str, str]] = ()) -> str:
    """The viewer with no mesh: it opens files chosen in the page."""
    return render_page(None, title=title, links=links)


def write_viewer(path: str | Path, value: Viewable, *, trace: Trace | None = None,
                 overwrite: bool = False, **options: Any) -> Path:
    """Write :func:`viewer_html` to ``path`` atomically (refusing to replace a file unless
    ``overwrite``); return the path."""
    target = Path(path)
    options.setdefault("source", None)
    write_text_atomic(target, viewer_html(value, trace=trace, **options), overwrite=overwrite)
    return target
