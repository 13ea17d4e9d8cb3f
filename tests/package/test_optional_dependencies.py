"""Optional parts behind extras: a bare ``import geomexact`` loads none of the heavy
packages, and a feature whose package is missing says which extra installs it (a clear
error and exit status 2 from the command, never a traceback)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

SQUARE = "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n"


def _run(code: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-c", code], cwd=cwd, capture_output=True,
                          text=True, timeout=120, check=False)


def test_a_bare_import_loads_no_heavy_package(tmp_path: Path) -> None:
    done = _run("import sys, json, geomexact; json.dump(sorted(sys.modules), sys.stdout)",
                tmp_path)
    loaded = set(json.loads(done.stdout))
    heavy = {"numpy", "matplotlib", "meshio", "hypothesis", "sympy", "h5py", "gmpy2",
             "geomexact.mesh2d.refinement.engines.lepp_kernel",
             "geomexact.mesh2d.delaunay.delaunay_kernel"}
    assert not heavy & loaded, sorted(heavy & loaded)


def test_the_first_use_of_a_name_loads_its_module(tmp_path: Path) -> None:
    done = _run("import sys, geomexact; geomexact.Mesh2; "
                "print('geomexact.mesh2d.snapshot' in sys.modules, 'matplotlib' in sys.modules)",
                tmp_path)
    assert done.stdout.split() == ["True", "False"]


@pytest.mark.parametrize("command", [
    ["info", "square.off"], ["info", "square.off", "--json"], ["check", "square.off"],
    ["check", "square.off", "--strict"], ["convert", "square.off", "out.pslg"],
    ["info", "copy.pslg"],
])
def test_small_commands_load_no_numpy(tmp_path: Path, command: list[str]) -> None:
    """Issue 25, item 5: a command on a small file loads neither NumPy nor a compiled
    kernel (formats load on first use, small meshes are built and summarised without
    arrays: the same answers, ``tests/mesh2d/test_mesh_arrays.py``)."""
    (tmp_path / "square.off").write_text(SQUARE)
    (tmp_path / "copy.pslg").write_text("v 0 0\nv 1 0\nv 1 1\nv 0 1\nt 0 1 2\nt 0 2 3\n")
    done = _run("import sys, json\nfrom geomexact.cli import main\ncode = main("
                f"{command!r})\nprint(json.dumps([code, sorted(sys.modules)]))", tmp_path)
    code, loaded = json.loads(done.stdout.strip().splitlines()[-1])
    assert code == 0, done.stderr
    heavy = {"numpy", "meshio", "matplotlib", "sympy",
             "geomexact.mesh2d.refinement.engines.lepp_kernel",
             "geomexact.mesh2d.delaunay.delaunay_kernel"}
    assert not heavy & set(loaded), sorted(heavy & set(loaded))


@pytest.mark.parametrize(
    ("blocked", "command", "extra"),
    [
        ("matplotlib", ["view", "square.off", "-o", "square.png"], "pictures"),
        ("meshio", ["convert", "square.off", "square.vtk"], "meshio"),
    ],
)
def test_a_missing_extra_is_named(tmp_path: Path, blocked: str, command: list[str],
                                  extra: str) -> None:
    (tmp_path / "square.off").write_text(SQUARE)
    done = _run(f"import sys; sys.modules[{blocked!r}] = None\n"
                f"from geomexact.cli import main\nsys.exit(main({command!r}))", tmp_path)
    assert done.returncode == 2, done.stderr
    assert f"geomexact[{extra}]" in done.stderr
    assert "Traceback" not in done.stderr
    assert not (tmp_path / command[-1]).exists()


def test_strategies_without_hypothesis_name_the_extra(tmp_path: Path) -> None:
    done = _run("import sys; sys.modules['hypothesis'] = None\n"
                "try:\n    import geomexact.strategies\n"
                "except ImportError as error:\n    print(error)\n", tmp_path)
    assert "geomexact[strategies]" in done.stdout
