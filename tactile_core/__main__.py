"""``python -m tactile_core``: the ``tactile`` command."""

import sys

from .cli import main

if __name__ == "__main__":
    sys.exit(main())
