"""``python -m synergrasp``: the command line (`synergrasp.cli`)."""

import sys

from .cli import main

if __name__ == "__main__":
    sys.exit(main())
