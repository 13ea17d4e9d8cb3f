"""The package's layers import only downward (``docs/design.md``): every ``import`` in
``geomexact/`` (top-level or inside a function, Python or Cython) is checked against the
layer table, and no module inside the package imports the top-level facade."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[2] / "geomexact"

LAYERS: dict[str, int] = {
    "_lazy_exports": 0,
    "_public_names": 0,
    "_version": 0,
    "errors": 0,
    "kernel": 1,
    "trace": 2,
    "mesh2d": 3,
    "mesh3d": 3,
    "strategies": 4,
    "io": 5,
    "viz": 6,
    "server": 7,
    "cli": 8,
    "__main__": 9,
}
"""Top-level part -> its layer; a module may import its own layer's part and lower
layers, never a higher layer nor another part of its own layer."""


def _part(module: str) -> str:
    """``geomexact.mesh2d.ops`` -> ``mesh2d``; the facade ``geomexact`` -> ``""``."""
    pieces = module.split(".")
    return pieces[1] if len(pieces) > 1 else ""


def _module_name(path: Path) -> str:
    relative = path.relative_to(PACKAGE.parent).with_suffix("")
    parts = list(relative.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _imports_of(path: Path) -> list[tuple[int, str]]:
    """(line, imported module) for every geomexact import in the file."""
    text = path.read_text(encoding="utf-8")
    if path.suffix in (".pyx", ".pxd"):
        found = []
        for number, line in enumerate(text.splitlines(), start=1):
            match = re.match(r"\s*(?:from\s+(geomexact[\w.]*)\s+c?import\b\s*([\w, ]*)"
                             r"|c?import\s+(geomexact[\w.]*))", line)
            if match:
                module = match.group(1) or match.group(3)
                if module == "geomexact" and match.group(2):
                    found += [(number, f"geomexact.{n.split(' as ')[0].strip()}")
                              for n in match.group(2).split(",")]
                else:
                    found.append((number, module))
        return found
    found = []
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.Import):
            found += [(node.lineno, a.name) for a in node.names
                      if a.name.split(".")[0] == "geomexact"]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            if node.module == "geomexact":
                # ``from geomexact import x``: a submodule, or the facade's name x
                found += [(node.lineno, f"geomexact.{a.name}") for a in node.names]
            elif node.module.split(".")[0] == "geomexact":
                found.append((node.lineno, node.module))
    return found


def _sources() -> list[Path]:
    return sorted(p for p in PACKAGE.rglob("*") if p.suffix in (".py", ".pyx", ".pxd"))


def test_the_layer_table_covers_every_part() -> None:
    parts = {_part(_module_name(p)) for p in _sources()} - {""}
    assert parts <= set(LAYERS), f"parts without a layer: {sorted(parts - set(LAYERS))}"


@pytest.mark.parametrize("path", _sources(), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_imports_go_only_downward(path: Path) -> None:
    importer = _module_name(path)
    if importer == "geomexact":
        return  # the facade re-exports every layer
    own = _part(importer)
    wrong = []
    for line, module in _imports_of(path):
        part = _part(module)
        if part not in LAYERS:
            wrong.append(f"line {line}: imports the facade name {module!r} (import it "
                         "from the module that defines it)")
        elif part != own and LAYERS[part] >= LAYERS[own]:
            wrong.append(f"line {line}: {own} (layer {LAYERS[own]}) imports {module} "
                         f"(layer {LAYERS[part]})")
    assert not wrong, f"{path.relative_to(PACKAGE)}:\n" + "\n".join(wrong)


def test_the_checker_sees_an_upward_import(tmp_path: Path) -> None:
    """The walk itself works: an upward import written into a file is found."""
    sample = tmp_path / "sample.py"
    sample.write_text("def f():\n    from geomexact.cli import main\n    return main\n")
    assert _imports_of(sample) == [(2, "geomexact.cli")]


def test_values_do_not_change_after_construction() -> None:
    """No ``object.__setattr__`` on a frozen value after it is made: only in
    ``__attrs_post_init__`` (its derived fields, at construction) or ``__setstate__``;
    a snapshot defers work through ``kernel.derived.Derived`` (issue 25, item 3)."""
    allowed = {"__attrs_post_init__", "__setstate__", "__init__"}
    wrong = []
    for path in _sources():
        if path.suffix != ".py":
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for function in ast.walk(tree):
            if not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            if function.name in allowed:
                continue
            for node in ast.walk(function):
                if (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
                        and node.func.attr == "__setattr__"
                        and isinstance(node.func.value, ast.Name)
                        and node.func.value.id == "object"):
                    wrong.append(f"{path.relative_to(PACKAGE)}:{node.lineno} in "
                                 f"{function.name}")
    assert not wrong, "a frozen value changed after construction:\n" + "\n".join(wrong)
