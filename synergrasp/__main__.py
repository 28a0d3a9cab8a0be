"""``python -m synergrasp``: the command line (`synergrasp.cli`)."""

import sys

from .cli import main

sys.exit(main())
