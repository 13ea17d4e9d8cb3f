"""Build-time helpers of the documentation site (``docs/conf.py`` calls :func:`setup`).

At ``builder-inited`` they write ``docs/_generated/`` (ignored by git):

- ``specs/NAME.md``: one page per file of ``specs/`` that includes it, so that the specs
  are part of the site; a page's links to ``../specs/NAME.md`` are pointed there while it
  is read (``source-read``), its file on disk unchanged;
- ``cli-help.md``: the reference of every command from its real ``--help``
  (``docs/cli_reference.py``);
- ``facade.md``: the names of the facade ``geomexact`` with the module of each;
- ``tour/``: the pictures of ``docs/tour.md`` and their captions, made by the package
  (``docs/tour_pictures.py``).
"""

from __future__ import annotations

import re
import time
from pathlib import Path
from typing import Any

from sphinx.util import logging

logger = logging.getLogger(__name__)

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
GENERATED = DOCS / "_generated"
SPECS = ROOT / "specs"


def write_if_changed(path: Path, text: str) -> None:
    """Write ``text`` unless the file already holds it (Sphinx then rereads nothing)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")


def spec_pages() -> list[str]:
    """Write one page per spec under ``_generated/specs/``; return their docnames."""
    names = []
    for spec in sorted(SPECS.rglob("*.md")):
        relative = spec.relative_to(SPECS)
        page = GENERATED / "specs" / relative
        up = "../" * (len(relative.parts) + 2)
        write_if_changed(page, f"```{{include}} {up}specs/{relative.as_posix()}\n```\n")
        names.append(f"_generated/specs/{relative.with_suffix('').as_posix()}")
    return names


_ROLE = re.compile(r":[a-z]+:`~?([^`<]+?)(?: <[^>]*>)?`")


def facade_page() -> str:
    """The Markdown of the list of the facade's names (``geomexact.__all__``)."""
    import importlib

    import geomexact

    lines = ["# The facade `geomexact`", "",
             "`from geomexact import NAME` works for each name below; it is loaded from the "
             "module beside it on first use (`import geomexact` itself loads nothing heavy).",
             "", "| name | defined in | |", "|---|---|---|"]
    homes: dict[str, str] = geomexact._HOMES
    for name in sorted(homes, key=str.lower):
        home = homes[name]
        doc = (getattr(importlib.import_module(home), name).__doc__ or "").strip()
        first = " ".join(doc.split("\n\n")[0].split()).replace("|", "\\|")
        first = _ROLE.sub(lambda m: f"`{m.group(1).split('.')[-1]}`", first)
        first = first if len(first) <= 160 else first[:157].rsplit(" ", 1)[0] + " …"
        lines.append(f"| {{py:obj}}`{name} <{home}.{name}>` | `{home}` | {first} |")
    return "\n".join(lines) + "\n"


_SPEC_LINK = re.compile(r"\]\(\.\./specs/")


def _source_read(app: Any, docname: str, source: list[str]) -> None:
    if "/" not in docname:
        source[0] = _SPEC_LINK.sub("](_generated/specs/", source[0])


def _builder_inited(app: Any) -> None:
    import cli_reference  # docs/, on sys.path (conf.py)
    import tour_pictures

    spec_pages()
    cli_reference.write_reference(GENERATED / "cli-help.md")
    write_if_changed(GENERATED / "facade.md", facade_page())
    began = time.perf_counter()
    seconds = tour_pictures.make_all(GENERATED / "tour")
    logger.info("tour pictures: %s (%.1f s)", ", ".join(
        f"{name} {s:.1f} s" for name, s in seconds.items()), time.perf_counter() - began)


def setup(app: Any) -> None:
    app.connect("builder-inited", _builder_inited)
    app.connect("source-read", _source_read)
