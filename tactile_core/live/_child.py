"""The stream process with the OSC server and the LSL outlets beside its output thread.

``python -m tactile_core.live._child CMD_FD EVENTS_FD`` is the stream process of
:mod:`tactile_core.device.process` with a :class:`~._services_host.ServicesHost` as its
extension: the tuner's stream child (``open_stream(..., child=tactile_core.live.CHILD_MODULE)``),
so that another program's points reach the output thread without crossing into the GUI's
process.
"""

from __future__ import annotations

import sys

from ..device.process import main as stream_main
from ._osc_server import SWITCH_INTERVAL_S
from ._services_host import ServicesHost


def services(streamer, profile, send) -> ServicesHost:
    """The extension: the services, with the stream process's switch interval."""
    return ServicesHost(streamer, profile, send, switch_interval_s=SWITCH_INTERVAL_S)


def main(argv=None) -> int:
    """The stream process, with the services as its extension."""
    return stream_main(argv, extension=services)


if __name__ == "__main__":
    sys.exit(main())
