"""The documentation site stays in sync with the program.

The site itself is built by ``scripts/test`` (``sphinx-build -W``, warnings are errors),
not here, so that CI builds it once.  These tests are cheap: they read ``docs/`` and the
argument parser.
"""

from __future__ import annotations

import importlib.util
import re
import sys
from pathlib import Path
from types import ModuleType

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"


def docs_module(name: str) -> ModuleType:
    """Import ``docs/NAME.py`` (the docs folder is not a package)."""
    spec = importlib.util.spec_from_file_location(f"docs_{name}", DOCS / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


def test_every_command_has_a_section_in_cli_md() -> None:
    """Each command of the parser (and each ``trace`` subcommand) has its heading in
    docs/cli.md: ``## info``, ``### trace show``, …"""
    reference = docs_module("cli_reference")
    headings = set(re.findall(r"^#{2,4} (.+?)\s*$", (DOCS / "cli.md").read_text("utf-8"),
                              flags=re.MULTILINE))
    commands = [" ".join(words) for words, _ in reference.commands()]
    assert len(commands) >= 14
    missing = [name for name in commands if name not in headings]
    assert not missing, f"docs/cli.md has no section for: {', '.join(missing)}"


def test_the_generated_reference_has_every_help_text() -> None:
    """The generated page holds ``geomexact COMMAND --help`` of every command, verbatim."""
    reference = docs_module("cli_reference")
    text = reference.reference()
    for words, parser in reference.commands():
        assert f"`geomexact {' '.join(words)}`" in text
        with reference._columns(reference.WIDTH):
            assert parser.format_help().rstrip() in text
        assert f"(#{reference.anchor(words)})" in text


def test_cli_md_names_only_real_commands() -> None:
    """Every ``## name`` section of docs/cli.md below the command list is a command (or
    a general section)."""
    reference = docs_module("cli_reference")
    commands = {" ".join(words) for words, _ in reference.commands()}
    general = {"Exit codes", "Memory budget", "Files and formats", "JSON output", "--version"}
    sections = re.findall(r"^## (.+?)\s*$", (DOCS / "cli.md").read_text("utf-8"),
                          flags=re.MULTILINE)
    unknown = [s for s in sections if s not in commands and s not in general]
    assert not unknown, f"docs/cli.md has sections for no command: {unknown}"


def test_every_page_is_in_the_toctree() -> None:
    """Each Markdown page of docs/ is listed in a toctree (Sphinx would warn otherwise,
    but only at build time)."""
    pages = [page for page in DOCS.rglob("*.md")
             if "_build" not in page.parts and "_generated" not in page.parts]
    listed = set()
    for page in pages:
        for block in re.findall(r"```\{toctree\}\n(.*?)```", page.read_text("utf-8"),
                                flags=re.DOTALL):
            for line in block.splitlines():
                if line and not line.startswith(":"):
                    listed.add((page.parent / line).resolve())
    missing = [str(page.relative_to(DOCS)) for page in pages
               if page != DOCS / "index.md" and page.with_suffix("").resolve() not in listed]
    assert not missing, f"pages in no toctree: {missing}"


def test_install_page_example_runs() -> None:
    """The Python example of docs/install.md runs as written."""
    text = (DOCS / "install.md").read_text("utf-8")
    blocks = re.findall(r"^```python\n(.*?)^```", text, flags=re.MULTILINE | re.DOTALL)
    assert blocks
    for block in blocks:
        exec(compile(block, "docs/install.md", "exec"), {"__name__": "install_example"})


def test_the_tour_pictures_are_made_at_build_time() -> None:
    """docs/tour.md includes one generated fragment per picture that
    docs/tour_pictures.py makes (the pictures themselves are made by the build)."""
    pytest.importorskip("matplotlib")
    tour = docs_module("tour_pictures")
    text = (DOCS / "tour.md").read_text("utf-8")
    for name in tour.PICTURES:
        assert f"_generated/tour/{name}.md" in text


def test_the_benchmarks_command_has_help() -> None:
    """``python -m benchmarks --help`` works (nothing is run)."""
    import subprocess

    done = subprocess.run([sys.executable, "-m", "benchmarks", "--help"], cwd=ROOT,
                          capture_output=True, text=True, timeout=120, check=False)
    assert done.returncode == 0, done.stderr
    assert "--quick" in done.stdout and "docs/performance.md" in done.stdout


def test_the_performance_page_says_how_it_was_made() -> None:
    """docs/performance.md is the output of ``python -m benchmarks`` and says so, with the
    machine it ran on."""
    text = (DOCS / "performance.md").read_text("utf-8")
    assert re.search(r"This page was made by `python -m benchmarks[^`]*`", text)
    for needed in ("## The machine", "CPU", "cores", "load average", "Python"):
        assert needed in text
    for image in re.findall(r"!\[[^\]]*\]\(([^)]+)\)", text):
        assert (DOCS / image).is_file(), image
