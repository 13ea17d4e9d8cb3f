"""The headless Chromium the browser tests share (Debian's ``chromium`` driven by
Playwright): a pytest plugin (``pytest_plugins`` in ``tests/conftest.py``) with the
session fixture ``browser``.  Tests marked ``browser`` are skipped when no Chromium is on
PATH, and tests using the fixture when Playwright is missing."""

from __future__ import annotations

import shutil
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

CHROMIUM_NAMES = ("chromium", "chromium-browser", "google-chrome")
CHROMIUM_FLAGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
]


def chromium() -> str:
    """The path of a Chromium on PATH; skips the test when there is none."""
    for name in CHROMIUM_NAMES:
        found = shutil.which(name)
        if found:
            return found
    pytest.skip("needs a headless chromium on PATH")


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Tests marked ``browser`` are skipped when no Chromium is on PATH."""
    if any(shutil.which(name) for name in CHROMIUM_NAMES):
        return
    skip_browser = pytest.mark.skip(reason="needs a headless chromium on PATH")
    for item in items:
        if "browser" in item.keywords:
            item.add_marker(skip_browser)


@pytest.fixture(scope="session")
def browser() -> Iterator[Any]:
    """One headless Chromium for the session (each test makes its own context)."""
    sync_api = pytest.importorskip("playwright.sync_api")
    with sync_api.sync_playwright() as playwright:
        # Playwright makes a new, empty user-data directory for each launch
        launched = playwright.chromium.launch(executable_path=chromium(), args=CHROMIUM_FLAGS)
        yield launched
        launched.close()


def canvas_inked(tab: Any, canvas: str = "view") -> int:
    """How many pixels of the page's canvas ``canvas`` are not (nearly) white."""
    inked: int = tab.evaluate("""(id) => {
        const c = document.getElementById(id);
        const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
        let n = 0;
        for (let i = 0; i < d.length; i += 4)
            if (d[i] < 250 || d[i + 1] < 250 || d[i + 2] < 250) n++;
        return n; }""", canvas)
    return inked


def canvas_image(tab: Any, canvas: str = "view") -> str:
    """The canvas ``canvas`` as a data URL (to compare two drawings)."""
    url: str = tab.evaluate("(id) => document.getElementById(id).toDataURL()", canvas)
    return url


def open_offline_page(browser: Any, path: Path,
                      ready: str = "#stats-table tr") -> Iterator[tuple[Any, list[str], list[str]]]:
    """Open the page file ``path`` in a new 1000 × 700 context that aborts every request
    not for a ``file:`` URL; yield the tab, the errors it logs (console errors and
    uncaught exceptions) and the URLs it requests, once ``ready`` is in the page; close
    the context afterwards.  For ``yield from`` in a fixture."""
    errors: list[str] = []
    requests: list[str] = []
    context = browser.new_context(viewport={"width": 1000, "height": 700})
    context.route("**/*", lambda route: route.continue_()
                  if route.request.url.startswith("file://") else route.abort())
    tab = context.new_page()
    tab.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    tab.on("pageerror", lambda e: errors.append(str(e)))
    tab.on("request", lambda r: requests.append(r.url))
    tab.goto(path.as_uri())
    tab.wait_for_selector(ready, state="attached")
    try:
        yield tab, errors, requests
    finally:
        context.close()
