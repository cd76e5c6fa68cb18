"""The stream process: ``python -m tactile_core.stream CMD_FD EVENTS_FD``.

:class:`~tactile_core.stream.process.StreamerProcess` starts it. The entry is the package rather
than ``tactile_core.stream.process``: the package imports that module, and running a module
already imported makes ``runpy`` warn on every stream start.
"""

import sys

from .process import main

if __name__ == "__main__":
    sys.exit(main())
