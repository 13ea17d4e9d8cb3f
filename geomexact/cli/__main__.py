"""``python -m geomexact.cli``: the same as the ``geomexact`` command."""

from geomexact.cli import main

raise SystemExit(main())
