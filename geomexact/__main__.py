"""``python -m geomexact``: the same as the ``geomexact`` command."""

from geomexact.cli import run

run()
