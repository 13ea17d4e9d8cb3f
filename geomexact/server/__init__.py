"""``geomexact serve``: a small local HTTP server for looking at meshes.

It lists the mesh files of a directory and opens each in the viewer (with a trace, the
step slider), and it refines uploaded meshes: the upload form sends a mesh file, the server
runs the library on it (never a shell) and answers with the viewer of the result and its
trace.  It is meant for one person on their own machine:

- it listens on the loopback interface unless ``host`` names another; on loopback it
  answers only requests whose ``Host`` is a loopback name (no DNS rebinding), and it
  refuses uploads posted from other sites (``Origin`` another site's or ``null``,
  ``Sec-Fetch-Site`` not same-origin);
- it reads nothing outside the directory: a served file and every file a reader opens
  beside it (a Triangle ``.ele``'s ``.node``, ``.neigh``, ``.poly``) are resolved and must
  lie inside it, and the reader runs on a sandbox of links to those files only;
- a request body is at most ``max_upload_bytes`` (refused before it is read, and the page
  still reaches the client); every piece of library work (reading a file, triangulating,
  refining, building a page) runs in a separate process capped at
  ``memory_limit_bytes`` and killed after ``time_limit`` seconds; at most ``jobs`` uploads
  and, apart from them, ``view_jobs`` views run at once (more requests get "busy");
- a bad file gets a page naming the file, the line and the problem, never quoting the
  file's text; a client that goes away is one log line.

Actions offered for uploads are in :data:`ACTIONS`: ``triangulate`` always, ``refine``
when :mod:`geomexact.mesh2d.refinement.api` is installed.  Specification: ``specs/viewer.md``.

Modules: :mod:`~geomexact.server.options` (:class:`ServeOptions`),
:mod:`~geomexact.server.actions` (what an upload can be run through),
:mod:`~geomexact.server.jobs` (the work behind each page),
:mod:`~geomexact.server.bounded` (running a job in a child process with a time limit),
:mod:`~geomexact.server.form_data` (an upload's form, read in linear time),
:mod:`~geomexact.server.listing` (the served directory's files),
:mod:`~geomexact.server.served_files` (what a read opens, confined to the directory),
:mod:`~geomexact.server.read_failures` (error messages without the files' text),
:mod:`~geomexact.server.pages` (the server's own HTML pages) and
:mod:`~geomexact.server.http_server` (HTTP).
"""

from __future__ import annotations

from geomexact.server.actions import ACTIONS, Action, Outcome, available_actions
from geomexact.server.bounded import JobFailed, run_bounded
from geomexact.server.form_data import parse_multipart
from geomexact.server.http_server import JobSlots, MeshServer, is_loopback, make_server, serve
from geomexact.server.jobs import safe_name, upload_job, view_job
from geomexact.server.options import ServeOptions

__all__ = [
    "ACTIONS",
    "Action",
    "JobFailed",
    "JobSlots",
    "MeshServer",
    "Outcome",
    "ServeOptions",
    "available_actions",
    "is_loopback",
    "make_server",
    "parse_multipart",
    "run_bounded",
    "safe_name",
    "serve",
    "upload_job",
    "view_job",
]
