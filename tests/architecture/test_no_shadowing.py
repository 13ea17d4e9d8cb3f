"""No package exports a name equal to one of its submodules: ``import geomexact.x.y as m``
always gives the module ``y``, never a function that hides it."""

from __future__ import annotations

import importlib
import pkgutil
from types import ModuleType

import pytest

import geomexact


def _packages() -> list[str]:
    names = ["geomexact"]
    for info in pkgutil.walk_packages(geomexact.__path__, "geomexact."):
        if info.ispkg:
            names.append(info.name)
    return sorted(names)


def _submodules(package: ModuleType) -> set[str]:
    return {info.name for info in pkgutil.iter_modules(package.__path__)}


def _exported(package: ModuleType) -> set[str]:
    """Names the package offers: its ``__all__`` and every public name bound in it."""
    names = set(getattr(package, "__all__", ()))
    names |= {name for name, value in vars(package).items()
              if not name.startswith("_") and not isinstance(value, ModuleType)}
    return names


@pytest.mark.parametrize("name", _packages())
def test_no_export_equals_a_submodule(name: str) -> None:
    package = importlib.import_module(name)
    clash = _exported(package) & _submodules(package)
    assert not clash, f"{name} exports names equal to its submodules: {sorted(clash)}"


@pytest.mark.parametrize("name", _packages())
def test_every_submodule_is_reachable_as_a_module(name: str) -> None:
    package = importlib.import_module(name)
    for sub in sorted(_submodules(package) - {"__main__"}):
        try:
            module = importlib.import_module(f"{name}.{sub}")
        except ImportError as error:  # an optional compiled kernel that is not built
            if "kernel" in sub or "cfilters" in sub:
                continue
            raise AssertionError(f"{name}.{sub} does not import: {error}") from error
        assert getattr(package, sub) is module, f"{name}.{sub} is hidden by another value"


def test_the_check_sees_a_clash() -> None:
    """A package exporting a function named like its submodule is caught."""
    fake = ModuleType("fake")
    fake.__all__ = ["ops"]  # type: ignore[attr-defined]
    assert _exported(fake) & {"ops", "snapshot"} == {"ops"}
