"""docs/debugging.md as written: its commands, run in order through the CLI, print the
output it shows (``[…]`` standing for text that varies) and exit as it says; its Python
block runs; its ``>>>`` session passes as a doctest; the numbers its prose quotes are
those of the traces; its picture is the one ``trace diff --picture`` draws, under 150 KB;
and the guide's index links it."""

from __future__ import annotations

import contextlib
import doctest
import io
import os
import re
import shlex
from collections import Counter
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from matplotlib.image import imread

from geomexact import read_trace
from geomexact.cli import main
from geomexact.viz.scene import step_label

DOCS = Path(__file__).resolve().parents[2] / "docs"
GUIDE = DOCS / "debugging.md"
PICTURE = DOCS / "images" / "debugging-diff.png"
BLOCK = re.compile(r"^```(\w+)\n(.*?)^```", re.S | re.M)
ANY = "[…]"


def blocks() -> list[tuple[str, str]]:
    return BLOCK.findall(GUIDE.read_text(encoding="utf-8"))


def matches(expected: list[str], found: list[str]) -> bool:
    """Line by line; ``[…]`` stands for any text within a line, or for any lines when it
    is a whole line."""
    if not expected:
        return not found
    head = expected[0]
    if head.strip() == ANY:
        return any(matches(expected[1:], found[i:]) for i in range(len(found) + 1))
    if not found:
        return False
    pattern = ".*".join(re.escape(part) for part in head.split(ANY))
    return re.fullmatch(pattern, found[0]) is not None and matches(expected[1:], found[1:])


def commands(body: str) -> list[tuple[str, list[str]]]:
    """(command line, expected output lines) of a console block."""
    found: list[tuple[str, list[str]]] = []
    for line in body.splitlines():
        if line.startswith("$ "):
            found.append((line[2:], []))
        else:
            found[-1][1].append(line)
    return found


@pytest.fixture(scope="module")
def session(tmp_path_factory: pytest.TempPathFactory) -> Iterator[dict[str, Any]]:
    """Every block of the page run in order in an empty folder."""
    folder = tmp_path_factory.mktemp("debugging")
    before = Path.cwd()
    os.chdir(folder)
    results: dict[str, Any] = {"folder": folder, "runs": [], "namespace": {}}
    try:
        yield from _run_blocks(results)
    finally:
        os.chdir(before)


def _run_blocks(results: dict[str, Any]) -> Iterator[dict[str, Any]]:
    for language, body in blocks():
        if language == "text":  # the OFF file (Pygments has no OFF lexer)
            Path("square.off").write_text(body, encoding="utf-8")
        elif language == "console":
            for line, expected in commands(body):
                words = shlex.split(line)
                assert words[0] == "geomexact", line
                out, err = io.StringIO(), io.StringIO()
                with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
                    code = main(words[1:])
                results["runs"].append((line, code, out.getvalue() + err.getvalue(),
                                        expected))
        elif language == "python":
            exec(compile(body, str(GUIDE), "exec"), results["namespace"])
        elif language == "pycon":
            test = doctest.DocTestParser().get_doctest(body, {}, "debugging.md", str(GUIDE),
                                                       0)
            runner = doctest.DocTestRunner(verbose=False)
            out = io.StringIO()
            runner.run(test, out=out.write)
            results["doctest"] = (runner.failures, runner.tries, out.getvalue())
    yield results


def test_the_page_has_every_kind_of_block() -> None:
    kinds = Counter(language for language, _ in blocks())
    assert kinds == {"text": 1, "console": 5, "python": 1, "pycon": 1}


def test_every_command_prints_what_the_page_shows(session: dict[str, Any]) -> None:
    """Each command's output is the text under it; trace bisect and trace diff exit 1 (a
    property fails, the traces differ), the others 0, as the page says."""
    runs = session["runs"]
    assert [line.split()[1:3] for line, *_ in runs] == [
        ["refine", "square.off"], ["trace", "show"], ["trace", "bisect"],
        ["trace", "diff"], ["view", "square.off"]]
    for line, code, output, expected in runs:
        assert code == (1 if line.split()[1:3] in (["trace", "bisect"], ["trace", "diff"])
                        else 0), (line, output)
        assert matches(expected, output.rstrip("\n").splitlines()), (line, output)


def test_the_doctest_session_passes(session: dict[str, Any]) -> None:
    failures, tries, report = session["doctest"]
    assert tries >= 10
    assert failures == 0, report


def test_the_numbers_in_the_prose_are_those_of_the_traces(session: dict[str, Any]) -> None:
    text = " ".join(GUIDE.read_text(encoding="utf-8").split())
    run = read_trace(session["folder"] / "run.trace.jsonl")
    planted = session["namespace"]["planted"]
    assert len(read_trace(session["folder"] / "planted.trace.jsonl")) == len(planted)
    at = session["namespace"]["at"]
    assert at == 40
    later = len(run) - at
    kept = len(planted) - at - 1
    assert f"It prints `{len(planted)} {at} {planted.steps[at]}`" in text
    assert f"{later - kept} of the {later} later steps" in text
    assert f"every one of the {len(run)} steps is a `bisect`" in text
    assert set(Counter(step.op for step in run.steps)) == {"bisect"}
    counts = Counter(step.op for step in planted.steps)
    assert counts["flip"] == 1 and planted.steps[at].op == "flip"
    assert f"`all ({len(planted)})`, `bisect ({counts['bisect']})`, `flip (1)`" in text
    assert f"`step {at + 1}: {step_label(planted.steps[at])} (+2 / −2 triangles)`" in text
    assert f"the result, step {len(planted)}" in text
    applied = re.search(r"`applied` counts .*?: (\d+) for all", text)
    assert applied and int(applied.group(1)) < 2 * len(planted)
    page = (session["folder"] / "planted.html").read_text(encoding="utf-8")
    assert 'id="op-filter"' in page and 'id="step-go"' in page


def test_the_picture_is_the_one_trace_diff_draws(session: dict[str, Any]) -> None:
    """docs/images/debugging-diff.png is what the page's trace diff command draws (same
    size, nearly the same pixels: fonts may render a little differently), under 150 KB,
    and the page shows it."""
    assert PICTURE.stat().st_size < 150_000
    made = imread(session["folder"] / "debugging-diff.png")
    kept = imread(PICTURE)
    assert made.shape == kept.shape
    assert abs(made - kept).mean() < 0.01
    assert "](images/debugging-diff.png)" in GUIDE.read_text(encoding="utf-8")


def test_the_index_links_the_page() -> None:
    assert "(debugging.md)" in (DOCS / "index.md").read_text(encoding="utf-8")


@pytest.mark.browser
def test_the_viewer_walkthrough_shows_what_the_page_says(session: dict[str, Any],
                                                         browser: Any) -> None:
    """In headless Chromium, planted.html does what section 7 describes: it opens on the
    last step; the op filter's options; |◀ then ▶ with "flip" chosen lands on step 41 with
    the quoted label and position; ▶ again says there is no later flip; typing 41 jumps
    there; no console error, no request but the page."""
    text = " ".join(GUIDE.read_text(encoding="utf-8").split())
    context = browser.new_context(viewport={"width": 1200, "height": 800})
    errors: list[str] = []
    requests: list[str] = []
    context.route("**/*", lambda route: route.continue_()
                  if route.request.url.startswith("file://") else route.abort())
    page = context.new_page()
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.on("request", lambda r: requests.append(r.url))
    try:
        page.goto((session["folder"] / "planted.html").as_uri())
        page.wait_for_selector("#stat-vertices", state="attached")
        last = page.evaluate("() => geomexactViewer.model.step")
        assert f"the result, step {last}" in text
        options = page.locator("#op-filter option").all_inner_texts()
        assert f"`{'`, `'.join(options)}`" in text
        page.select_option("#op-filter", "flip")
        page.click("#first")
        page.click("#next")
        label = page.inner_text("#step-label")
        position = page.inner_text("#filter-position")
        assert f"`{label}` and `{position}`" in text
        page.click("#next")
        assert f"`{page.inner_text('#step-message')}`" in text
        page.click("#first")
        page.fill("#step-go", "41")
        page.press("#step-go", "Enter")
        assert page.inner_text("#step-label") == label
        assert "type `41` and press Enter" in text
    finally:
        context.close()
    assert errors == []
    assert all(url.startswith("file://") for url in requests), requests
