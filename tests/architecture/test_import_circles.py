"""No import circle anywhere in ``geomexact/`` (issue 25): the graph of every import of a
package module by another, at module level or inside a function (imports under
``if TYPE_CHECKING:`` are left out: they never run), has no strongly connected component of
two or more modules.  A snapshot reaches its transient, its step table and its compiled
accelerations through the mesh kind its package binds (``trace.protocols.MeshKind``), not by
importing the modules built on it."""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[2] / "geomexact"


def _module_name(path: Path, root: Path) -> str:
    parts = list(path.relative_to(root.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _typing_only(tree: ast.AST) -> set[int]:
    """The ids of the nodes under ``if TYPE_CHECKING:``."""
    found: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and ast.unparse(node.test) in (
                "TYPE_CHECKING", "typing.TYPE_CHECKING"):
            for inner in node.body:
                found.update(id(sub) for sub in ast.walk(inner))
    return found


def import_graph(root: Path) -> dict[str, set[str]]:
    """Module -> the package's modules it imports (a name imported from a module counts as
    the module; a submodule imported from a package as the submodule)."""
    modules = {_module_name(path, root): path for path in sorted(root.rglob("*.py"))}
    top = root.name

    def resolve(name: str) -> str | None:
        while name and name not in modules:
            name = name.rpartition(".")[0]
        return name or None

    graph: dict[str, set[str]] = {}
    for module, path in modules.items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        skipped = _typing_only(tree)
        targets: set[str | None] = set()
        for node in ast.walk(tree):
            if id(node) in skipped:
                continue
            if isinstance(node, ast.Import):
                targets.update(resolve(alias.name) for alias in node.names
                               if alias.name.split(".")[0] == top)
            elif isinstance(node, ast.ImportFrom):
                source = node.module or ""
                if node.level:
                    base = module.split(".")
                    if path.name != "__init__.py":
                        base = base[:-1]
                    base = base[:len(base) - (node.level - 1)]
                    source = ".".join(base + ([node.module] if node.module else []))
                if source.split(".")[0] != top:
                    continue
                for alias in node.names:
                    full = f"{source}.{alias.name}"
                    targets.add(full if full in modules else resolve(source))
        graph[module] = {target for target in targets if target and target != module}
    return graph


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of two or more modules (Tarjan, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []
    for root in graph:
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in graph:
                    continue
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph[child]))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    found.append(sorted(component))
    return found


def test_no_import_circle_in_the_package() -> None:
    graph = import_graph(PACKAGE)
    assert len(graph) > 150  # the walk read the package
    found = circles(graph)
    assert not found, "import circles:\n" + "\n".join(
        f"  {' <-> '.join(component)}" for component in found)


def test_the_checker_finds_a_circle_through_a_function_level_import(tmp_path: Path) -> None:
    """A circle closed by an import inside a function is found; one closed only under
    ``if TYPE_CHECKING:`` is not (it never runs)."""
    package = tmp_path / "geomexact"
    (package / "inner").mkdir(parents=True)
    (package / "__init__.py").write_text("")
    (package / "inner" / "__init__.py").write_text("")
    (package / "inner" / "a.py").write_text("from geomexact.inner.b import g\n")
    (package / "inner" / "b.py").write_text(
        "def g():\n    from geomexact.inner import a\n    return a\n")
    (package / "inner" / "c.py").write_text("from geomexact.inner.d import h\n")
    (package / "inner" / "d.py").write_text(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n"
        "    from geomexact.inner.c import x\n\ndef h():\n    return 1\n")
    assert circles(import_graph(package)) == [["geomexact.inner.a", "geomexact.inner.b"]]
