"""Every spec states the seven items of issue 16's checklist.

Each file of ``specs/`` (formats included) ends with a ``## Checklist`` section holding
seven ``###`` subsections, in this order: Definitions, Tie rules, Degenerate cases,
Preconditions, What is exact, Termination, References.  A subsection may point to the
section above that holds the details, but it may not be empty; where an item does not
apply it says in a sentence why.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SPECS = ROOT / "specs"

CHECKLIST = "Checklist"
ITEMS = ("Definitions", "Tie rules", "Degenerate cases", "Preconditions", "What is exact",
         "Termination", "References")
MIN_TEXT = 30
"""Characters of text (whitespace aside) a subsection must hold at least."""

_HEADING = re.compile(r"^(#{1,6}) (.+?)\s*$")
_FENCE = re.compile(r"^\s*(```|~~~)")


def sections(text: str) -> list[tuple[int, str, str]]:
    """``(level, title, body)`` of every Markdown heading of ``text``, in order; lines in
    fenced code blocks are body, never headings.  The body runs to the next heading of
    any level."""
    found: list[tuple[int, str, list[str]]] = []
    fenced = False
    for line in text.splitlines():
        if _FENCE.match(line):
            fenced = not fenced
        heading = None if fenced else _HEADING.match(line)
        if heading:
            found.append((len(heading.group(1)), heading.group(2), []))
        elif found:
            found[-1][2].append(line)
    return [(level, title, "\n".join(body)) for level, title, body in found]


def checklist_problems(text: str) -> list[str]:
    """What is wrong with the checklist of a spec's text (nothing: an empty list)."""
    found = sections(text)
    starts = [i for i, (level, title, _) in enumerate(found)
              if level == 2 and title == CHECKLIST]
    if len(starts) != 1:
        return [f"{len(starts)} '## {CHECKLIST}' sections (want 1)"]
    inside = []
    for level, title, body in found[starts[0] + 1:]:
        if level <= 2:
            break
        inside.append((level, title, body))
    items = [(title, body) for level, title, body in inside if level == 3]
    titles = [title for title, _ in items]
    problems = [f"no '### {item}'" for item in ITEMS if item not in titles]
    problems += [f"'### {title}' is not an item of the checklist"
                 for title in titles if title not in ITEMS]
    if not problems and titles != list(ITEMS):
        problems.append(f"items out of order: {titles}")
    for title, body in items:
        # a subsection's text: its body and that of its deeper headings
        following = inside[[t for _, t, _ in inside].index(title) + 1:]
        deeper = []
        for level, _, more in following:
            if level <= 3:
                break
            deeper.append(more)
        words = re.sub(r"\s+", "", "\n".join([body, *deeper]))
        if len(words) < MIN_TEXT:
            problems.append(f"'### {title}' is empty or nearly ({len(words)} characters)")
        elif re.search(r"\b(TODO|TBD|FIXME)\b", body):
            problems.append(f"'### {title}' is a placeholder")
    return problems


SPEC_FILES = sorted(SPECS.rglob("*.md"))


def test_the_specs_are_found() -> None:
    """The parametrised test below runs over the real specs, formats included."""
    names = {path.relative_to(SPECS).as_posix() for path in SPEC_FILES}
    assert len(names) >= 20
    assert {"delaunay.md", "lepp.md", "formats/off.md", "formats/registry.md"} <= names


@pytest.mark.parametrize("path", SPEC_FILES,
                         ids=[p.relative_to(SPECS).as_posix() for p in SPEC_FILES])
def test_every_spec_has_the_seven_items(path: Path) -> None:
    problems = checklist_problems(path.read_text("utf-8"))
    assert not problems, f"{path.relative_to(ROOT)}: " + "; ".join(problems)


_SPEC = "# A spec\n\nText.\n\n## Checklist\n" + "".join(
    f"\n### {item}\nThis item is stated here in a full sentence of words.\n"
    for item in ITEMS)


def test_a_complete_checklist_passes() -> None:
    assert checklist_problems(_SPEC) == []
    # a deeper heading inside an item carries its text
    nested = _SPEC.replace("### Termination\nThis item",
                           "### Termination\n#### Known limits\nThis item")
    assert checklist_problems(nested) == []


@pytest.mark.parametrize("item", ITEMS)
def test_a_missing_item_is_found(item: str) -> None:
    text = _SPEC.replace(f"### {item}\n", "")
    assert checklist_problems(text) == [f"no '### {item}'"]


def test_an_empty_item_is_found() -> None:
    text = _SPEC.replace("### Preconditions\nThis item is stated here in a full sentence "
                         "of words.\n", "### Preconditions\n\n")
    assert checklist_problems(text) == ["'### Preconditions' is empty or nearly (0 characters)"]
    placeholder = _SPEC.replace(
        "### Tie rules\nThis item is stated here in a full sentence of words.",
        "### Tie rules\nTODO: write the tie rules of this algorithm.")
    assert checklist_problems(placeholder) == ["'### Tie rules' is a placeholder"]


def test_a_spec_without_a_checklist_or_with_headings_in_code_is_found() -> None:
    assert checklist_problems("# A spec\n\n## Definitions\nText.\n") == [
        "0 '## Checklist' sections (want 1)"]
    # a heading inside a fenced block is code, not a section
    fenced = _SPEC.replace("### References\n", "```\n### References\n```\n")
    assert "no '### References'" in checklist_problems(fenced)
    # an item after the checklist ended does not count
    moved = _SPEC.replace("### References\n", "## Afterwards\n### References\n")
    assert "no '### References'" in checklist_problems(moved)
    swapped = _SPEC.replace("### Definitions", "### Swap").replace(
        "### Tie rules", "### Definitions").replace("### Swap", "### Tie rules")
    assert checklist_problems(swapped) == [
        f"items out of order: {['Tie rules', 'Definitions', *ITEMS[2:]]}"]
