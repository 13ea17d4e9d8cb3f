"""How ``geomexact serve`` runs: :class:`ServeOptions` and its defaults."""

from __future__ import annotations

from pathlib import Path

import attrs

DEFAULT_PORT = 8765
DEFAULT_MAX_UPLOAD_BYTES = 16 * 1024 * 1024
DEFAULT_TIME_LIMIT = 60.0
DEFAULT_JOBS = 2


@attrs.frozen
class ServeOptions:
    """How the server runs (see :mod:`geomexact.server`)."""

    directory: Path
    host: str = "127.0.0.1"
    port: int = DEFAULT_PORT
    max_upload_bytes: int = DEFAULT_MAX_UPLOAD_BYTES
    time_limit: float = DEFAULT_TIME_LIMIT
    jobs: int = DEFAULT_JOBS
