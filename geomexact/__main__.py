"""``python -m geomexact``: the same as the ``geomexact`` command."""

import sys

from geomexact.cli import main

sys.exit(main())
