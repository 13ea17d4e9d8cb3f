"""Every code example of the documentation site runs as written (issue 16).

Each page's fenced blocks are run in order in an empty folder (``superior.poly``, the
bundled Lake Superior PSLG, copied there as the pages say, and ``../shared/data`` read
where a page names it: those examples skip when it is absent):

- ``pycon`` blocks (``>>>`` sessions) pass as doctests, sharing one namespace per page;
- ``python`` blocks run;
- ``console`` blocks: each ``$ geomexact …`` line runs through the CLI in-process, exits 0
  (or what the page says) and prints the output shown under it (``…`` standing for any
  text, a line of ``…`` for any lines; times and memory excepted; a JSON object shown
  is compared key by key, exactly);
- ``sh`` blocks: each ``geomexact …`` line runs and exits 0;
- the synopses (plain blocks of ``geomexact COMMAND [--option …]`` lines) name only the
  options the parser has, with its choices, and cli.md's name every option;
- every inline ``geomexact COMMAND --option`` of a page names a real command and option.

docs/debugging.md and docs/viewer.md run in their own tests
(``tests/trace/test_debugging_docs.py``, ``tests/viz/test_viz_docs.py``), as do the Python
blocks of docs/octree.md (``tests/mesh3d/test_octree_docs.py``), docs/meshing-a-part.md
(``tests/mesh3d/test_meshing_a_part_docs.py``) and docs/install.md
(``test_docs_site.py``); here only their other blocks are checked.
"""

from __future__ import annotations

import argparse
import contextlib
import doctest
import functools
import importlib.util
import io
import json
import re
import shlex
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

import pytest
from helpers.paths import SHARED_DATA

from geomexact.cli import main

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
FENCE = re.compile(r"^```([^\n`]*)\n(.*?)^```[ \t]*$", re.M | re.S)
ELLIPSIS = "…"
UNTIMED = ("seconds", "peak memory mb", "peak_memory_mb", "stage_seconds")
"""Output that varies from run to run: not compared."""


@dataclass
class Block:
    language: str
    body: str
    line: int


def blocks(page: str) -> list[Block]:
    text = (DOCS / page).read_text("utf-8")
    return [Block(m.group(1).strip(), m.group(2), text.count("\n", 0, m.start()) + 1)
            for m in FENCE.finditer(text)]


# --- running commands ------------------------------------------------------------------


@dataclass
class Run:
    line: str
    code: int
    out: str
    err: str


def shell_words(line: str) -> list[str]:
    """The words of a command line of a page, ``../shared/data`` made absolute."""
    words = shlex.split(line, comments=True)
    assert words and words[0] == "geomexact", line
    if any("../shared/data" in word for word in words):
        if not SHARED_DATA.is_dir():
            pytest.skip(f"shared test data not found at {SHARED_DATA}")
        words = [word.replace("../shared/data", str(SHARED_DATA)) for word in words]
    return words


def run(line: str) -> Run:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(shell_words(line)[1:])
        except SystemExit as exit_:  # argparse's usage errors
            code = int(exit_.code or 0)
    return Run(line, code, out.getvalue(), err.getvalue())


def session(body: str) -> list[tuple[str, list[str]]]:
    """(command line, output lines shown) of a console block; ``\\`` continues a line."""
    found: list[tuple[str, list[str]]] = []
    continued = False
    for line in body.splitlines():
        if continued:
            found[-1] = (found[-1][0][:-1] + " " + line.strip(), found[-1][1])
        elif line.startswith("$ "):
            found.append((line[2:], []))
        else:
            assert found, f"output before any command: {line!r}"
            found[-1][1].append(line)
        continued = found[-1][0].endswith("\\") if found else False
    return found


def _line_pattern(shown: str) -> re.Pattern[str]:
    shown = shown.strip()
    key = re.split(r"\s{2,}", shown)[0]
    if key in UNTIMED:
        return re.compile(re.escape(key) + r"\s+\S+")
    parts = [re.escape(part) for part in shown.split(ELLIPSIS)]
    pattern = ".*".join(parts)
    pattern = re.sub(r"(?:\\ )+", r"\\s+", pattern)
    pattern = re.sub(r"\d+(?:\\\.\d+)?(\\s\+s\b)", r"[\\d.]+\1", pattern)  # "0.10 s"
    return re.compile(pattern)


def lines_match(shown: list[str], found: list[str]) -> bool:
    """Line by line; a line of ``…`` stands for any lines."""
    if not shown:
        return not found
    head = shown[0].strip()
    if head == ELLIPSIS:
        return any(lines_match(shown[1:], found[i:]) for i in range(len(found) + 1))
    if not found:
        return False
    return (_line_pattern(head).fullmatch(found[0].strip()) is not None
            and lines_match(shown[1:], found[1:]))


JSON_PAIR = re.compile(r'"(\w+)":\s*("(?:[^"\\]|\\.)*"|\[[^\]]*\]|\{[^}]*\}|true|false|null'
                       r"|-?\d[\d.eE+-]*)")


def json_matches(shown: list[str], output: str) -> None:
    """Every ``"key": value`` shown is the output's, exactly (values with ``…`` and
    times excepted)."""
    found = json.loads(output)
    pairs = JSON_PAIR.findall(" ".join(shown))
    assert pairs, shown
    for key, value in pairs:
        if ELLIPSIS in value or key in UNTIMED:
            assert key in found, key
            continue
        assert found.get(key, "<missing>") == json.loads(value), (key, value, found.get(key))


def check_output(result: Run, shown: list[str]) -> None:
    shown = [line for line in shown if line.strip()]
    if not shown:
        return
    if shown[0].lstrip().startswith("{"):
        json_matches(shown, result.out)
        return
    both = (result.out + result.err).rstrip("\n").splitlines()
    assert (lines_match(shown, result.out.rstrip("\n").splitlines())
            or lines_match(shown, both)), (result.line, result.out + result.err)


def run_console(block: Block, codes: dict[str, int] | None = None) -> list[Run]:
    """Run a console block's commands; each exits as ``codes`` says (0 by default) and
    prints what the page shows."""
    runs = []
    for line, shown in session(block.body):
        result = run(line)
        expected = (codes or {}).get(line, 0)
        assert result.code == expected, (line, result.code, result.err)
        check_output(result, shown)
        runs.append(result)
    return runs


def run_sh(block: Block) -> list[Run]:
    """Run a shell block's ``geomexact`` lines; each exits 0."""
    runs = []
    for line in block.body.splitlines():
        if line.strip() and not line.lstrip().startswith("#"):
            result = run(line)
            assert result.code == 0, (line, result.err)
            runs.append(result)
    return runs


def run_doctest(block: Block, page: str, globs: dict[str, Any]) -> int:
    """A ``>>>`` block as a doctest in the page's namespace; returns the examples run."""
    parser = doctest.DocTestParser()
    test = parser.get_doctest(block.body, globs, page, str(DOCS / page), block.line)
    runner = doctest.DocTestRunner(
        verbose=False, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    report = io.StringIO()
    runner.run(test, out=report.write, clear_globs=False)
    globs.update(test.globs)  # the next block of the page goes on from here
    assert runner.failures == 0, report.getvalue()
    return runner.tries


@pytest.fixture()
def folder(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """An empty folder, made current, holding ``superior.poly`` (and the same at
    ``geomexact/data/superior.poly``, the path in a checkout, beside the other packaged
    data such as ``mos.device``)."""
    superior = resources.files("geomexact") / "data" / "superior.poly"
    data = superior.read_bytes()
    (tmp_path / "superior.poly").write_bytes(data)
    (tmp_path / "geomexact" / "data").mkdir(parents=True)
    (tmp_path / "geomexact" / "data" / "superior.poly").write_bytes(data)
    device = resources.files("geomexact") / "data" / "mos.device"
    (tmp_path / "geomexact" / "data" / "mos.device").write_bytes(device.read_bytes())
    monkeypatch.chdir(tmp_path)
    return tmp_path


def run_page(page: str, skip: tuple[str, ...] = (),
             codes: dict[str, int] | None = None) -> dict[str, Any]:
    """Every block of PAGE in order (but the languages in SKIP); returns what ran."""
    globs: dict[str, Any] = {"__name__": f"docs_{Path(page).stem}"}
    done: dict[str, Any] = {"doctests": 0, "python": 0, "console": [], "sh": [],
                            "globs": globs}
    for block in blocks(page):
        if block.language in skip:
            continue
        if block.language == "pycon":
            done["doctests"] += run_doctest(block, page, globs)
        elif block.language == "python":
            exec(compile(block.body, str(DOCS / page), "exec"), globs)
            done["python"] += 1
        elif block.language == "console":
            done["console"] += run_console(block, codes)
        elif block.language == "sh":
            done["sh"] += run_sh(block)
    return done


# --- the pages ---------------------------------------------------------------------------


def test_tour(folder: Path) -> None:
    done = run_page("tour.md")
    assert done["doctests"] >= 12


def test_refine(folder: Path) -> None:
    done = run_page("refine.md")
    assert done["doctests"] >= 5
    refined, replayed = done["console"]
    digest = re.search(r"digest\s+([0-9a-f]{32})", refined.out)
    assert digest and f"digest {digest.group(1)}" in replayed.out


def test_polylla(folder: Path) -> None:
    done = run_page("polylla.md")
    assert done["doctests"] >= 5 and len(done["console"]) == 3
    assert (folder / "superior-convex.png").stat().st_size > 5000


def test_cuboid(folder: Path) -> None:
    done = run_page("cuboid.md")
    assert done["doctests"] >= 5 and len(done["console"]) == 2


def test_octree(folder: Path) -> None:
    """The quick console examples (the level-6 sphere is in the slow test below; the
    Python blocks run in tests/mesh3d/test_octree_docs.py)."""
    quick = [block for block in blocks("octree.md") if block.language == "console"
             and "--level 6" not in block.body]
    assert len(quick) == 3
    for block in quick:
        run_console(block)


@pytest.mark.slow
def test_octree_sphere(folder: Path) -> None:
    """``geomexact octree … --level 6 -o sphere.ele`` (about 10 s), then ``info``."""
    (block,) = [block for block in blocks("octree.md") if block.language == "console"
                and "--level 6" in block.body]
    run_console(block)


def test_papers(folder: Path) -> None:
    """The Mellado commands, whose triangles are the 35° row of the page's table; the
    Pineda ones (on ../shared/data) whose counts are those of table 5.1's row."""
    text = (DOCS / "papers.md").read_text("utf-8")
    mellado, pineda = [block for block in blocks("papers.md") if block.language == "sh"]
    row = re.search(r"^\| 35° \|.*$", text, re.M)
    assert row
    for result in run_sh(Block("sh", mellado.body.replace(".off", ".off --json"), 0)):
        assert f"{json.loads(result.out)['triangles']:,}" in row.group(0)
    if not SHARED_DATA.is_dir():
        pytest.skip(f"shared test data not found at {SHARED_DATA}")
    row = re.search(r"^\| `500poisson.off` \|.*$", text, re.M)
    assert row
    program, thesis = (json.loads(result.out) for result in run_sh(pineda))
    cells = [cell.strip() for cell in row.group(0).split("|")]
    concave, inserted = cells[3].split(" / "), cells[4].split(" / ")
    for report in (program, thesis):
        assert report["polygons"] == 306 and f"{report['polygons']} / 306" in row.group(0)
    # the columns: thesis / program / pineda-thesis / pineda / default
    assert concave[1] == str(program["nonconvex"]) and concave[3] == f"**{program['nonconvex']}**"
    assert concave[0] == str(thesis["nonconvex"]) and concave[2] == f"**{thesis['nonconvex']}**"
    assert inserted[3] == f"**{program['inserted_edges']}**" == f"**{inserted[1]}**"
    assert inserted[2] == str(thesis["inserted_edges"])


def test_cli(folder: Path) -> None:
    """The error line of a bad file, the cuboid run and its replays, and the info example
    (on ../shared/data)."""
    consoles = [block for block in blocks("cli.md") if block.language == "console"]
    assert len(consoles) == 3
    (error,) = [block for block in consoles if "bad.off" in block.body]
    (info,) = [block for block in consoles if "shared/data" in block.body]
    (replay,) = [block for block in consoles if "cuboid" in block.body]
    (folder / "bad.off").write_text("OFF\n3 1 0\n0 0 0\n1 0 0\none 1 0\n3 0 1 2\n")
    (result,) = run_console(error, {"geomexact info bad.off": 2})
    assert result.out == ""
    runs = run_console(replay)
    assert len(runs) == 3
    for suffix in ("node", "ele"):
        assert ((folder / f"again.{suffix}").read_bytes()
                == (folder / f"final.{suffix}").read_bytes())
    run_console(info)


def test_cli_version() -> None:
    """The kernels' lines that cli.md shows are those ``geomexact --version`` prints."""
    (block,) = [block for block in blocks("cli.md") if "  lepp: " in block.body]
    result = run("geomexact --version")
    assert result.code == 0
    printed = " ".join(result.out.split())
    for kernel in re.split(r"\n(?=  \w+: )", block.body.strip("\n")):
        assert " ".join(kernel.split()) in printed, kernel


# --- synopses and inline commands ---------------------------------------------------------


@functools.cache
def parsers() -> dict[tuple[str, ...], argparse.ArgumentParser]:
    """Every command's parser by its words (``docs/cli_reference.py``, as the site)."""
    spec = importlib.util.spec_from_file_location("docs_cli_reference_examples",
                                                  DOCS / "cli_reference.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return dict(module.commands())


def command_of(words: list[str],
               known: dict[tuple[str, ...], argparse.ArgumentParser]) -> tuple[str, ...]:
    """The longest command named by WORDS (after ``geomexact``)."""
    for size in (2, 1):
        if tuple(words[:size]) in known:
            return tuple(words[:size])
    return ()


def options_of(parser: argparse.ArgumentParser) -> dict[str, argparse.Action]:
    return {name: action for action in parser._actions for name in action.option_strings}


SYNOPSIS_PAGES = ("cli.md", "refine.md", "cuboid.md", "octree.md", "viewer.md")


def synopses() -> list[tuple[str, str]]:
    """(page, text) of each synopsis: a ``geomexact …`` line of a plain block with its
    indented continuation lines."""
    found = []
    for page in SYNOPSIS_PAGES:
        for block in blocks(page):
            if block.language:
                continue
            for chunk in re.split(r"\n(?=geomexact )", block.body):
                if chunk.startswith("geomexact ") and "[" in chunk:
                    found.append((page, chunk))
    return found


def test_synopses_name_real_options_and_choices() -> None:
    known = parsers()
    checked = 0
    for page, text in synopses():
        words = text.split()[1:]
        command = command_of(words, known)
        if not command:  # geomexact [--version] [-h] COMMAND ...
            assert words[0] == "[--version]", (page, text)
            continue
        options = options_of(known[command])
        named = re.findall(r"(?<![\w-])(--?[a-zA-Z][\w-]*)", text)
        unknown = [name for name in named if name not in options]
        assert not unknown, f"{page}: {' '.join(command)}: no such options {unknown}"
        for name, choices in re.findall(r"(--[\w-]+) \{?([\w-]+(?:[|,][\w-]+)+)", text):
            action = options[name]
            if action.choices is not None:
                shown = set(re.split(r"[|,]", choices))
                assert shown <= {str(choice) for choice in action.choices}, (page, name, shown)
        if page == "cli.md":
            missing = sorted({name for name, action in options.items()
                              if name.startswith("--") and name not in named
                              and f"-{name.lstrip('-')[0]}" not in named
                              and not isinstance(action, argparse._HelpAction)
                              and not any(alias in named for alias in action.option_strings)})
            assert not missing, f"cli.md: {' '.join(command)}: synopsis lacks {missing}"
        checked += 1
    assert checked >= 15


INLINE = re.compile(r"`(geomexact [^`]+)`")


@pytest.mark.parametrize("page", sorted(path.name for path in DOCS.glob("*.md")))
def test_inline_commands_name_real_options(page: str) -> None:
    """Each inline ``geomexact COMMAND …`` names a command, and only its options."""
    known = parsers()
    text = (DOCS / page).read_text("utf-8")
    for span in INLINE.findall(" ".join(text.split())):
        words = span.split()[1:]
        if not words or words[0].startswith(("-", ELLIPSIS)) or words[0] in ("COMMAND",
                                                                            "X.Y.Z"):
            continue
        if words[0] == "trace" and len(words) > 1 and "|" in words[1]:
            words = ["trace", words[1].split("|")[0], *words[2:]]
        command = command_of(words, known)
        assert command, f"{page}: `{span}` names no command"
        options = options_of(known[command])
        named = re.findall(r"(?<![\w./-])(--?[a-zA-Z][\w-]*)", " ".join(words[len(command):]))
        unknown = [name for name in named if name not in options]
        assert not unknown, f"{page}: `{span}`: {' '.join(command)} has no {unknown}"


def test_every_page_with_examples_is_checked() -> None:
    """Each page's runnable blocks are of a kind run here or in the page's own test."""
    own = {"debugging.md", "viewer.md", "install.md", "index.md"}
    for path in sorted(DOCS.glob("*.md")):
        if path.name in own:
            continue
        for block in blocks(path.name):
            lines = block.body.lstrip().splitlines()
            if block.language == "" and lines and lines[0].startswith("$ "):
                pytest.fail(f"{path.name}:{block.line}: a session in a plain block "
                            "(label it console to have it run)")
            if block.language == "python":
                assert path.name in ("octree.md", "meshing-a-part.md"), (
                    f"{path.name}:{block.line}: use >>>")


def test_meshing_a_part(folder: Path) -> None:
    """The device session always; the spot session where ../shared/data is (its Python
    block runs in tests/mesh3d/test_meshing_a_part_docs.py)."""
    consoles = [block for block in blocks("meshing-a-part.md") if block.language == "console"]
    assert len(consoles) == 2
    run_console(consoles[1])
    assert (folder / "mos.vtu").stat().st_size > 10_000
    run_console(consoles[0])  # skips without ../shared/data


def test_coming_from(folder: Path) -> None:
    """The arrays session for users of the triangle package."""
    done = run_page("coming-from.md")
    assert done["doctests"] >= 4
