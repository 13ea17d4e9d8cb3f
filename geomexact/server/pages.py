"""The server's own HTML pages (no script): :func:`index_page` (the served files and the
upload form) and :func:`error_page`."""

from __future__ import annotations

import html
import urllib.parse
from http import HTTPStatus
from pathlib import Path

from geomexact.server.actions import ACTIONS, CRITERIA, available_actions
from geomexact.server.listing import is_trace, listed_files
from geomexact.server.options import ServeOptions

INDEX_CSP = (
    "default-src 'none'; style-src 'unsafe-inline'; img-src data:; form-action 'self'; "
    "base-uri 'none'"
)
"""The policy of the server's own pages (in a meta element; the viewer pages carry theirs).
Every response also has the header ``Content-Security-Policy: frame-ancestors 'none'``
(a directive that only works as a header): no other site can frame these pages."""

PAGE_CSS = """
body { font: 15px/1.5 system-ui, -apple-system, "Segoe UI", Roboto, Arial, sans-serif;
       color: #14213d; margin: 0 auto; max-width: 60rem; padding: 1rem 1.5rem 3rem; }
h1 { font-size: 1.4rem; } h2 { font-size: 1.1rem; margin-top: 2rem; }
table { border-collapse: collapse; width: 100%; }
th, td { text-align: left; padding: 0.25rem 0.6rem; border-bottom: 1px solid #e3e8ef; }
td.size { text-align: right; font-variant-numeric: tabular-nums; color: #5b6b82; }
code { font-size: 0.9em; } a { color: #1f5fbf; }
form { display: grid; grid-template-columns: max-content 1fr; gap: 0.5rem 1rem;
       align-items: center; background: #f6f8fb; padding: 1rem; border-radius: 6px; }
form .wide { grid-column: 1 / -1; }
.error { background: #fdecea; border: 1px solid #f3b8b3; color: #b3261e; padding: 0.7rem 1rem;
         border-radius: 6px; white-space: pre-wrap; }
.hint { color: #5b6b82; font-size: 0.9em; }
"""


def _page(title: str, body: str) -> str:
    return (
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
        f"<meta http-equiv=\"Content-Security-Policy\" content=\"{INDEX_CSP}\">\n"
        "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
        f"<title>{html.escape(title)}</title>\n<link rel=\"icon\" href=\"data:,\">\n"
        f"<style>{PAGE_CSS}</style>\n</head>\n<body>\n{body}\n</body>\n</html>\n"
    )


def _size(path: Path) -> str:
    try:
        size = float(path.stat().st_size)
    except OSError:
        return "-"
    for unit in ("B", "kB", "MB", "GB"):
        if size < 1024 or unit == "GB":
            return f"{size:.0f} {unit}" if unit == "B" else f"{size:.1f} {unit}"
        size /= 1024
    return "-"  # pragma: no cover


def _upload_form(options: ServeOptions) -> str:
    actions = available_actions()
    choices = "".join(
        f'<option value="{name}">{html.escape(ACTIONS[name].label)}</option>' for name in actions
    )
    criteria = "".join(
        f'<option value="{name}">{name.replace("_", " ")}</option>' for name in CRITERIA
    )
    refine_fields = ""
    if "refine" in actions:
        refine_fields = f"""
<label for="criterion">criterion (refine)</label>
<span><select id="criterion" name="criterion">{criteria}</select>
<input id="value" name="value" value="0.001" size="10" aria-label="criterion value">
<span class="hint">an area, an angle in degrees (&lt; 60), a factor or a length;
exact numbers such as 1/300</span></span>
<label for="method">method (refine)</label>
<select id="method" name="method"><option value="centroid">Lepp-centroid</option>
<option value="bisection">Lepp-bisection</option>
<option value="quasi">Lepp quasi-Delaunay</option></select>
<label for="max_steps">max steps (refine)</label>
<input id="max_steps" name="max_steps" value="200000" size="10" inputmode="numeric">"""
    limit_mb = options.max_upload_bytes / (1024 * 1024)
    return f"""
<h2 id="upload">Upload a mesh</h2>
<form method="post" action="/upload" enctype="multipart/form-data">
<label for="files">file(s)</label>
<span><input id="files" name="files" type="file" multiple required>
<span class="hint">OFF, PSLG text, Triangle .poly / .node, or .ele with its .node (choose
both); at most {limit_mb:g} MB</span></span>
<label for="action">action</label>
<select id="action" name="action">{choices}</select>{refine_fields}
<span class="wide"><button type="submit">Run</button>
<span class="hint">runs in a separate process for at most {options.time_limit:g} s</span></span>
</form>"""


def index_page(options: ServeOptions) -> str:
    """The start page: the files of the directory and the upload form."""
    from geomexact import io

    root = options.directory.resolve()
    rows = []
    traces = []
    for path in listed_files(root):
        relative = path.relative_to(root).as_posix()
        quoted = urllib.parse.quote(relative)
        if is_trace(path.name):
            traces.append(
                f'<tr><td><a href="/view?trace={quoted}">{html.escape(relative)}</a></td>'
                f'<td>trace: opens with its input, step by step</td>'
                f'<td class="size">{_size(path)}</td></tr>'
            )
            continue
        format_name = io.detect_format(path)
        rows.append(
            f'<tr><td><a href="/view?file={quoted}">{html.escape(relative)}</a></td>'
            f"<td>{html.escape(format_name)}</td><td class=\"size\">{_size(path)}</td></tr>"
        )
    listing = ("<table><thead><tr><th>file</th><th>format</th><th>size</th></tr></thead>"
               f"<tbody>{''.join(rows + traces)}</tbody></table>"
               if rows or traces else
               '<p class="hint">No mesh files here (OFF, Triangle .ele/.node/.poly, '
               "PSLG text, meshio formats, traces).</p>")
    body = f"""<h1>geomexact · {html.escape(str(root))}</h1>
<p class="hint">Click a file to open it in the viewer.  <a href="/viewer">Open the viewer
empty</a> to look at files from this computer without uploading them.</p>
{listing}
{_upload_form(options)}"""
    return _page(f"geomexact · {root.name}", body)


def error_page(status: int, message: str, options: ServeOptions | None) -> str:
    """A page naming the problem, with the upload form again."""
    phrase = HTTPStatus(status).phrase
    form = _upload_form(options) if options is not None else ""
    body = (f"<h1>{status} {html.escape(phrase)}</h1>"
            f'<p class="error" role="alert">{html.escape(message)}</p>'
            f'<p><a href="/">← files</a></p>{form}')
    return _page(f"geomexact · {phrase}", body)
