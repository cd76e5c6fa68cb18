"""``tactile-tuner``: start the desktop tool.

``tactile-tuner [--device URL] [--profile FILE] [--preset FILE] [--screenshot PNG]``. With no
``--device`` it drives the built-in simulated array. ``--screenshot`` renders the main window
after start-up to a PNG and exits (works offscreen: ``QT_QPA_PLATFORM=offscreen``).
"""

from __future__ import annotations

import argparse
import signal
import sys
import traceback


def build_parser() -> argparse.ArgumentParser:
    """Command-line options of ``tactile-tuner``."""
    p = argparse.ArgumentParser(prog="tactile-tuner", description=__doc__.splitlines()[0])
    p.add_argument(
        "--device", metavar="URL", help="port or pyserial URL (default: simulated array)"
    )
    p.add_argument(
        "--profile", metavar="FILE", help="device profile JSON (default: the palm array)"
    )
    p.add_argument("--preset", metavar="FILE", help="start from this preset")
    p.add_argument(
        "--screenshot", metavar="PNG", help="save the main window to PNG after start-up and exit"
    )
    p.add_argument(
        "--tab",
        choices=("tune", "compare", "blind", "experiments"),
        default=None,
        help="tab to show first (useful with --screenshot)",
    )
    p.add_argument("--no-restore", action="store_true", help="ignore the last session's state")
    p.add_argument(
        "--realtime",
        action="store_true",
        help="real-time priority for the stream (Linux; needs an rtprio limit or root)",
    )
    return p


def main(argv=None) -> int:
    """Entry point of ``tactile-tuner``."""
    args = build_parser().parse_args(argv)

    from tactile_core.device import ProfileError, load_profile
    from tactile_core.presets import PresetError, load_preset

    try:
        profile = load_profile(args.profile)
        preset = load_preset(args.preset) if args.preset else None
    except (ProfileError, PresetError) as exc:
        print(f"tactile-tuner: error: {exc}", file=sys.stderr)
        return 2

    from PySide6 import QtCore, QtWidgets

    QtCore.QCoreApplication.setOrganizationName("tactile-tuner")
    QtCore.QCoreApplication.setApplicationName("tactile-tuner")
    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication(sys.argv[:1])

    from .window import MainWindow

    window = MainWindow(
        device_url=args.device,
        profile=profile,
        preset=preset,
        restore=not (args.no_restore or args.screenshot),
        realtime=args.realtime,
    )

    def excepthook(kind, value, tb):  # an error in a slot: report it, keep running
        traceback.print_exception(kind, value, tb)
        window.show_error(f"internal error: {kind.__name__}: {value}")

    sys.excepthook = excepthook
    # Ctrl-C, SIGTERM and SIGHUP close the window (all off first); a timer lets Python see the
    # signal.
    for name in ("SIGINT", "SIGTERM", "SIGHUP"):
        if hasattr(signal, name):
            signal.signal(getattr(signal, name), lambda *_: window.close())
    heartbeat = QtCore.QTimer()
    heartbeat.timeout.connect(lambda: None)
    heartbeat.start(200)

    tabs = {"tune": 0, "compare": 1, "blind": 2, "experiments": 3}
    if args.tab:
        window.tabs.setCurrentIndex(min(tabs[args.tab], window.tabs.count() - 1))
    window.resize(1400, 900)
    window.show()

    if args.screenshot:

        def shoot():
            window.grab().save(args.screenshot)
            print(f"saved {args.screenshot}")
            window.close()

        QtCore.QTimer.singleShot(1200, shoot)

    app.aboutToQuit.connect(window.device.shutdown)
    code = app.exec()
    return code


if __name__ == "__main__":
    sys.exit(main())
