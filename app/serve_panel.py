"""The OSC server's box in the device dock, the Array menu's serve and LSL actions, and
:func:`install_serve`, which gives the main window all of it."""

from __future__ import annotations

from PySide6 import QtCore, QtWidgets

from .serve import LOOPBACK, ServeController
from .texts import tip

COUNTERS = (
    ("malformed", "malformed"),
    ("unknown", "unknown"),
    ("non_finite", "non-finite"),
    ("flood_dropped", "over the rate limit"),
    ("timed_out", "released by timeout"),
)
"""The counters the box shows by name (``ServeStats`` fields); the others add up as "other"."""
OTHER = ("wrong_type", "out_of_range", "refused", "too_large", "kernel_dropped", "errors")


def counters_text(stats) -> str:
    """``malformed 0 · unknown 0 · …`` for a :class:`~tactile_core.serve.ServeStats`."""
    parts = [f"{name} {getattr(stats, key)}" for key, name in COUNTERS]
    other = sum(getattr(stats, key) for key in OTHER)
    return " · ".join([*parts, f"other {other}"])


def traffic_text(serve: ServeController, stats) -> str:
    """Where it listens, the message rate, the last sender, what plays."""
    if serve.serving == "starting":
        return "starting..."
    if serve.serving == "off":
        return "off" if stats is None else f"off (served {stats.messages} messages)"
    host, port = serve.address
    text = f"udp {host}:{port} · {stats.rate_hz:.0f} messages/s" if stats else f"udp {host}:{port}"
    if stats is not None:
        sender = stats.last_sender or "nobody yet"
        n = stats.active_points
        text += (
            f" · last sender {sender} · {n} point{'' if n == 1 else 's'}, playing {stats.playing}"
        )
    return text


class ServePanel(QtWidgets.QGroupBox):
    """A toggle with the address to listen on; the traffic and the counters while serving; the
    LSL outlets' state: each on a line of its own (the LSL state had been squeezed onto the
    counters' line, which made the window 1320 px wide at 1280 x 720)."""

    def __init__(self, serve: ServeController, parent=None):
        super().__init__("Driven by another program (OSC)", parent)
        self.setObjectName("serve_panel")
        self.serve = serve
        self.toggle = QtWidgets.QPushButton("Serve OSC")
        self.toggle.setObjectName("osc_toggle")
        self.toggle.setCheckable(True)
        self.host_edit = QtWidgets.QLineEdit(serve.host)
        self.host_edit.setObjectName("osc_host")
        self.host_edit.setMaximumWidth(120)
        self.host_edit.setMinimumWidth(  # an IPv4 address, whole
            self.host_edit.fontMetrics().horizontalAdvance("255.255.255.255") + 12
        )
        self.port_spin = QtWidgets.QSpinBox()
        self.port_spin.setObjectName("osc_port")
        self.port_spin.setRange(0, 65535)
        self.port_spin.setSpecialValueText("any")
        self.port_spin.setValue(serve.port)
        self.warning = QtWidgets.QLabel("beyond this machine!")
        self.warning.setObjectName("osc_warning")
        self.warning.setStyleSheet("color: #c0392b; font-weight: bold;")
        self.warning.setToolTip(tip(
            "Listening beyond this machine: anyone who can reach the port drives the array "
            "(there is no authentication)"
        ))  # fmt: skip
        self.traffic = QtWidgets.QLabel("off")
        self.traffic.setObjectName("osc_traffic")
        self.counters = QtWidgets.QLabel("")
        self.counters.setObjectName("osc_counters")
        self.lsl_label = QtWidgets.QLabel("")
        self.lsl_label.setObjectName("lsl_status")
        for label in (self.traffic, self.counters, self.lsl_label):
            label.setTextInteractionFlags(QtCore.Qt.TextInteractionFlag.TextSelectableByMouse)
            label.setTextFormat(QtCore.Qt.TextFormat.PlainText)  # a sender's address, as is
        grid = QtWidgets.QGridLayout(self)
        grid.setContentsMargins(4, 0, 4, 0)  # as tall as the device's own three rows
        grid.setVerticalSpacing(0)
        row = QtWidgets.QHBoxLayout()
        row.setSpacing(6)
        row.addWidget(self.toggle)
        row.addWidget(QtWidgets.QLabel("host"))
        row.addWidget(self.host_edit)
        row.addWidget(QtWidgets.QLabel("port"))
        row.addWidget(self.port_spin)
        row.addWidget(self.warning)
        row.addStretch(1)
        grid.addLayout(row, 0, 0)
        grid.addWidget(self.traffic, 1, 0)
        grid.addWidget(self.counters, 2, 0)
        grid.addWidget(self.lsl_label, 3, 0)
        self.toggle.setToolTip(tip(
            "Listen for OSC messages (/tactile/point x y [intensity], /tactile/method, "
            "/tactile/mu, /tactile/gamma, /tactile/shape, /tactile/off, as tactile serve) and "
            "render the points on the array with the method, mu and gamma set here: tune by "
            "feel while a game drives the point. Off: all off"
        ))  # fmt: skip
        self.host_edit.setToolTip(tip(
            "Where to listen: 127.0.0.1 is this machine only. Another address (0.0.0.0, a LAN "
            "address) lets other machines drive the array, without authentication"
        ))  # fmt: skip
        self.port_spin.setToolTip(tip("UDP port (any: a free port, shown once serving)"))
        self.counters.setToolTip(tip(
            "Messages that did nothing, by kind; other: wrong arguments, out of range, refused, "
            "dropped by the system, internal errors"
        ))  # fmt: skip
        self.toggle.toggled.connect(self._on_toggle_toggled)
        self.host_edit.textChanged.connect(self._on_host_edit_text_changed)
        self.port_spin.valueChanged.connect(lambda value: setattr(serve, "port", value))
        serve.changed.connect(self.show_state)
        serve.stats_changed.connect(self.show_stats)
        self.show_state()

    def _on_toggle_toggled(self, on: bool) -> None:
        self.serve.set_serving(on)
        self.show_state()

    def _on_host_edit_text_changed(self, text: str) -> None:
        self.serve.host = text.strip()
        self.warning.setVisible(self.serve.host not in LOOPBACK)

    def show_state(self) -> None:
        """The toggle, the address boxes and the LSL line as the controller has them."""
        serve = self.serve
        on = serve.serving != "off"
        self.toggle.blockSignals(True)
        self.toggle.setChecked(on)
        self.toggle.setText("Stop serving" if on else "Serve OSC")
        self.toggle.blockSignals(False)
        self.host_edit.setEnabled(not on)
        self.port_spin.setEnabled(not on)
        if self.host_edit.text().strip() != serve.host:
            self.host_edit.setText(serve.host)
        if self.port_spin.value() != serve.port:
            self.port_spin.setValue(serve.port)
        self.warning.setVisible(serve.host not in LOOPBACK)
        lsl = "off" if not serve.lsl_markers else serve.lsl_status
        levels = " and levels" if serve.lsl_markers and serve.lsl_levels else ""
        self.lsl_label.setText(f"LSL markers{levels}: {lsl}")
        self.show_stats(serve.stats)

    def show_stats(self, stats) -> None:
        """The traffic line and the counters."""
        self.traffic.setText(traffic_text(self.serve, stats))
        self.counters.setText("" if stats is None else counters_text(stats))
        self.counters.setVisible(stats is not None)  # (no empty line while never served)
        self.counters.setStatusTip("" if stats is None else stats.last_problem)


def add_serve_actions(window, serve: ServeController) -> None:
    """*Serve OSC*, *LSL markers* and *LSL: also the levels* at the end of the Array menu."""
    menu = next(a.menu() for a in window.menuBar().actions() if a.text() == "&Array")
    menu.addSeparator()
    serving = menu.addAction("Serve OSC (another program drives the array)")
    serving.setObjectName("serve_action")
    markers = menu.addAction("Lab Streaming Layer markers")
    markers.setObjectName("lsl_action")
    levels = menu.addAction("Lab Streaming Layer: also the levels")
    levels.setObjectName("lsl_levels_action")
    for action in (serving, markers, levels):
        action.setCheckable(True)
    serving.triggered.connect(serve.set_serving)
    markers.triggered.connect(lambda on: serve.set_lsl(on))
    levels.triggered.connect(lambda on: serve.set_lsl(serve.lsl_markers, on))

    def show() -> None:
        for action, on in ((serving, serve.serving != "off"), (markers, serve.lsl_markers),
                           (levels, serve.lsl_levels)):  # fmt: skip
            action.setChecked(on)
        levels.setEnabled(serve.lsl_markers)

    serve.changed.connect(show)
    show()


def install_serve(window) -> ServeController:
    """Give ``window`` (a ``MainWindow``) the OSC server and the LSL setting: the controller,
    its box in the device dock, its actions in the Array menu, and what excludes it."""
    serve = ServeController(window.state, window.device, window)
    serve.message_posted.connect(window.statusBar().showMessage)
    serve.error_raised.connect(window.show_error)

    def blocked() -> str:
        if window.experiments.running:
            return "the OSC server cannot run during an experiment run"
        if window.blind.session.active:
            return "the OSC server cannot run during a Blind A/B session"
        return ""

    serve.blocked = blocked
    window.blind.blind_changed.connect(lambda on: on and serve.set_serving(
        False, "OSC server off: the Blind A/B session plays the tuner's own scenes"))  # fmt: skip
    window.experiments.running_changed.connect(lambda on: on and serve.set_serving(
        False, "OSC server off: the run presents the tuner's own scenes"))  # fmt: skip
    gestures = window.tune.gestures
    can_pulse = gestures.can_pulse
    gestures.can_pulse = lambda: can_pulse() and serve.serving == "off"
    free_only = "Another program drives free points over OSC: MM and IM need a shape"

    def on_changed() -> None:
        serving = serve.serving != "off"
        if serving:  # the sender owns the array: no drawing, no tactor held
            gestures.set_draw_mode(False)
            gestures.end_pulse(restore=False)
        window.controls.method.set_free_only(free_only if serving else "")

    serve.changed.connect(on_changed)
    felt = window.device_panel.felt_cost  # the sender's points are not the scene's trace
    felt.live = lambda: "another program drives free points" if serve.serving != "off" else ""
    serve.changed.connect(felt.schedule)
    window.serve_panel = ServePanel(serve)
    window.device_panel.layout().addWidget(window.serve_panel, 0, 5, 4, 1)  # its four rows
    add_serve_actions(window, serve)
    return serve
