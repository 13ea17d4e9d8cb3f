"""Where the tests find the project and their data."""

from __future__ import annotations

import os
from pathlib import Path

PROJECT = Path(__file__).resolve().parents[2]
TEST_DATA = PROJECT / "tests" / "data"
SUPERIOR = PROJECT / "geomexact" / "data" / "superior.poly"
SHARED_DATA = Path(os.environ.get("GEOMEXACT_SHARED_DATA") or PROJECT.parent / "shared" / "data")
"""Third-party data: ``../shared/data``, or ``$GEOMEXACT_SHARED_DATA`` (set it to a missing
folder to run the suite as a clone without ``../shared`` does)."""


def read_superior() -> object:
    """The bundled Lake Superior PSLG (``geomexact/data/superior.poly``), read exactly."""
    from geomexact import io

    return io.read(SUPERIOR, format="poly")
