"""``tactile-tuner``: start the desktop tool.

``tactile-tuner [--device URL] [--profile FILE] [--preset FILE] [--screenshot PNG]``. With no
``--device`` it drives the built-in simulated array. ``--screenshot`` renders the main window
after start-up to a PNG and exits (works offscreen: ``QT_QPA_PLATFORM=offscreen``).
"""

from __future__ import annotations

import argparse
import re
import signal
import sys
import traceback


def _size(text: str) -> tuple[int, int]:
    found = re.fullmatch(r"([0-9]{1,6})[xX]([0-9]{1,6})", text)  # ASCII digits only: no 1_280
    if found is None:
        raise argparse.ArgumentTypeError(f"size must look like 1280x720, got {text!r}")
    w, h = int(found[1]), int(found[2])
    if not (320 <= w <= 10_000 and 240 <= h <= 10_000):
        raise argparse.ArgumentTypeError(f"size must be within 320x240 .. 10000x10000: {text}")
    return w, h


def build_parser() -> argparse.ArgumentParser:
    """Command-line options of ``tactile-tuner``."""
    p = argparse.ArgumentParser(prog="tactile-tuner", description=__doc__.splitlines()[0])
    p.add_argument(
        "--device",
        metavar="URL",
        help="a serial port, socket://HOST:PORT (tactile emulate --socket) or another "
        "pyserial URL, or audio:[NAME] for an audio interface (default: the simulated array)",
    )
    p.add_argument(
        "--profile",
        metavar="FILE",
        help="device profile: a JSON file or a known profile's name, e.g. belt-8 (default: the "
        "palm array)",
    )
    p.add_argument("--preset", metavar="FILE", help="start from this preset")
    p.add_argument(
        "--screenshot", metavar="PNG", help="save the main window to PNG after start-up and exit"
    )
    p.add_argument(
        "--tab",
        choices=("tune", "compare", "blind", "experiments", "editor"),
        default=None,
        help="tab to show first (useful with --screenshot); editor: the Tune tab with the "
        "pattern editor shown",
    )
    p.add_argument("--no-restore", action="store_true", help="ignore the last session's state")
    p.add_argument(
        "--size",
        metavar="WxH",
        type=_size,
        default=None,
        help="window size in pixels, e.g. 1280x720 (default: the last session's, on screen)",
    )
    p.add_argument("--theme", choices=("system", "light", "dark"), default="system", help="colours")
    p.add_argument(
        "--no-realtime",
        dest="realtime",
        action="store_false",
        help="do not ask for real-time priority for the stream (by default it is asked for; "
        "Linux grants it with an rtprio limit or to root, and the status says if not)",
    )
    p.add_argument("--realtime", action="store_true", help=argparse.SUPPRESS)  # the default
    p.add_argument("--bench", action="store_true", help="print the GUI's benchmark tables and exit")
    p.add_argument("--quick", action="store_true", help="with --bench: shorter runs")
    return p


def close_on_signals(window) -> None:
    """Ctrl-C, SIGTERM and SIGHUP close ``window`` without asking (all off first). The handler
    only posts the close: run in the handler, closing (which stops the stream and takes its
    locks) could wait for ever for a lock the interrupted code holds. A timer of the window's
    lets Python see a signal while Qt's loop runs."""
    from PySide6 import QtCore

    for name in ("SIGINT", "SIGTERM", "SIGHUP"):
        if hasattr(signal, name):
            signal.signal(
                getattr(signal, name), lambda *_: QtCore.QTimer.singleShot(0, window.close_now)
            )
    heartbeat = QtCore.QTimer(window)
    heartbeat.timeout.connect(lambda: None)
    heartbeat.start(200)


def requested_profile(name):
    """The device profile ``--profile`` names: a known profile's name (bundled or the user's)
    or a JSON file; None when it names none, so the window comes back on the last session's
    (it came back on the palm array whatever the last session had used).

    Raises
    ------
    ProfileError
        When ``name`` names no profile, or its file is invalid.
    """
    from tactile_core.device.profile import find_profile, load_profile, profile_names

    if name is None:
        return None
    return find_profile(name) if name in profile_names() else load_profile(name)


def main(argv=None) -> int:
    """Entry point of ``tactile-tuner``."""
    args = build_parser().parse_args(argv)
    if args.screenshot is not None:  # before Qt: a path that cannot be written is refused now
        from tactile_core._shared.outfile import OutputError, check_output

        try:
            check_output(args.screenshot, (".png",), "--screenshot")
        except OutputError as exc:
            print(f"tactile-tuner: error: {exc}", file=sys.stderr)
            return 2
    if args.bench:
        from .bench import run

        run(quick=args.quick)
        return 0

    from .preflight import check

    problem = check()
    if problem:  # before Qt, which would abort the process with a longer message
        print(f"tactile-tuner: {problem}", file=sys.stderr)
        return 1

    from tactile_core.device.profile import ProfileError
    from tactile_core.files.presets import PresetError, load_preset

    try:
        profile = requested_profile(args.profile)
        preset = load_preset(args.preset) if args.preset else None
    except (ProfileError, PresetError) as exc:
        print(f"tactile-tuner: error: {exc}", file=sys.stderr)
        return 2

    from PySide6 import QtCore, QtWidgets

    QtCore.QCoreApplication.setOrganizationName("tactile-tuner")
    QtCore.QCoreApplication.setApplicationName("tactile-tuner")
    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication(sys.argv[:1])
    if args.theme != "system":
        from .theme import apply_theme

        apply_theme(app, args.theme)

    from .window import MainWindow

    window = MainWindow(
        device_url=args.device,
        profile=profile,
        preset=preset,
        restore=not args.no_restore,  # a screenshot shows the session (and never saves it)
        realtime=args.realtime,
        remember=not args.screenshot,
    )

    def excepthook(kind, value, tb):  # an error in a slot: report it, keep running
        traceback.print_exception(kind, value, tb)
        window.show_error(f"internal error: {kind.__name__}: {value}")

    sys.excepthook = excepthook
    close_on_signals(window)

    tabs = {"tune": 0, "compare": 1, "blind": 2, "experiments": 3, "editor": 0}
    if args.tab:
        window.tabs.setCurrentIndex(min(tabs[args.tab], window.tabs.count() - 1))
    if args.tab == "editor":
        from .timeline import show_editor

        show_editor(window.timeline)
    if args.size:
        window.resize(*args.size)
    window.fit_to_screen(keep_size=args.size is not None)  # a size asked for is the size
    window.show()
    # again once the window manager has framed it: its title bar's real height
    QtCore.QTimer.singleShot(500, lambda: window.fit_to_screen(keep_size=args.size is not None))

    failed = []
    if args.screenshot:

        def shoot():
            from tactile_core._shared.outfile import atomic_file

            data = QtCore.QByteArray()
            buffer = QtCore.QBuffer(data)
            buffer.open(QtCore.QIODevice.OpenModeFlag.WriteOnly)
            try:
                if not window.grab().save(buffer, "PNG"):
                    raise OSError("the window could not be encoded as PNG")
                with atomic_file(args.screenshot, binary=True) as f:  # all or nothing
                    f.write(bytes(data))
            except OSError as exc:
                print(f"tactile-tuner: error: --screenshot {args.screenshot}: "
                      f"{exc.strerror or exc}", file=sys.stderr)  # fmt: skip
                failed.append(exc)
            else:
                print(f"saved {args.screenshot}")
            window.close()

        QtCore.QTimer.singleShot(1200, shoot)

    app.aboutToQuit.connect(window.device.shutdown)
    code = app.exec()
    return 1 if failed else code


if __name__ == "__main__":
    sys.exit(main())
