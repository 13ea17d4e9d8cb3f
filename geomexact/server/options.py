"""How ``geomexact serve`` runs: :class:`ServeOptions` and its defaults."""

from __future__ import annotations

from pathlib import Path

import attrs

DEFAULT_PORT = 8765
DEFAULT_MAX_UPLOAD_BYTES = 16 * 1024 * 1024
DEFAULT_TIME_LIMIT = 60.0
DEFAULT_JOBS = 2
DEFAULT_VIEW_JOBS = 2
DEFAULT_MEMORY_LIMIT_BYTES = 2048 * 1024 * 1024
DEFAULT_MAX_CONNECTIONS = 128


@attrs.frozen
class ServeOptions:
    """How the server runs (see :mod:`geomexact.server`): ``jobs`` upload jobs and
    ``view_jobs`` viewing jobs at once (two pools: uploads never make viewing busy), each
    job's process capped at ``memory_limit_bytes`` of address space (None: no cap) and
    stopped after ``time_limit`` seconds; at most ``max_connections`` connections answered
    at once (more wait, unaccepted, in the system's queue)."""

    directory: Path
    host: str = "127.0.0.1"
    port: int = DEFAULT_PORT
    max_upload_bytes: int = DEFAULT_MAX_UPLOAD_BYTES
    time_limit: float = DEFAULT_TIME_LIMIT
    jobs: int = DEFAULT_JOBS
    view_jobs: int = DEFAULT_VIEW_JOBS
    memory_limit_bytes: int | None = DEFAULT_MEMORY_LIMIT_BYTES
    max_connections: int = DEFAULT_MAX_CONNECTIONS
