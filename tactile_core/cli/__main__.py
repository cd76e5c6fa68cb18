"""``python -m tactile_core.cli``: the ``tactile`` command."""

import sys

from . import main

if __name__ == "__main__":
    sys.exit(main())
