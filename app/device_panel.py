"""The device panel: ports and audio devices, connect/disconnect, the device profile, the
stream's status line."""

from __future__ import annotations

import html
import re

from PySide6 import QtCore, QtWidgets
from serial.tools import list_ports

from tactile_core.device.audio import audio_output_of, audio_outputs
from tactile_core.device.link import SIMULATED_URLS
from tactile_core.device.profile import profile_names
from tactile_core.stream import MAX_LEAD_MS

from .device import DeviceController
from .felt_cost import FeltCost
from .texts import tip
from .widgets import ElidedLabel


class DevicePanel(QtWidgets.QWidget):
    """Ports, connect/disconnect, the device profile, and the stream's status line.

    The profile box lists the bundled profiles and the user's by name (choosing one emits
    :attr:`profile_chosen`); *File...* loads one from a file (:attr:`profile_requested`)."""

    profile_requested = QtCore.Signal()
    profile_chosen = QtCore.Signal(str)
    """The name of a known profile picked in the profile box."""

    def __init__(self, device: DeviceController, parent=None):
        super().__init__(parent)
        self.device = device
        layout = QtWidgets.QGridLayout(self)
        self.port_combo = QtWidgets.QComboBox()
        self.port_combo.setEditable(True)
        self.port_combo.setMinimumWidth(260)
        self.port_combo.lineEdit().setPlaceholderText(
            "port or URL: /dev/ttyUSB0, COM3, socket://host:port, audio:NAME"
        )
        self.refresh_button = QtWidgets.QPushButton("Refresh")
        self.connect_button = QtWidgets.QPushButton("Connect")
        self.connect_button.setObjectName("connect")
        self.disconnect_button = QtWidgets.QPushButton("Disconnect")
        self.disconnect_button.setObjectName("disconnect")
        self.profile_button = QtWidgets.QPushButton("File...")
        self.profile_combo = QtWidgets.QComboBox()
        self.profile_combo.setObjectName("profile")
        self.profile_combo.setSizeAdjustPolicy(
            QtWidgets.QComboBox.SizeAdjustPolicy.AdjustToContents
        )
        # elided rather than squeezing the OSC box (a belt's words left ".0.1" of its host)
        self.profile_label = ElidedLabel("")
        self.link_label = QtWidgets.QLabel()
        self.profile_label.setTextFormat(QtCore.Qt.TextFormat.PlainText)  # a profile's words
        self.link_label.setTextFormat(QtCore.Qt.TextFormat.RichText)  # bold, the name escaped
        self.lead_spin = QtWidgets.QDoubleSpinBox()
        self.lead_spin.setObjectName("lead")
        self.lead_spin.setRange(0.0, MAX_LEAD_MS)
        self.lead_spin.setSingleStep(5.0)
        self.lead_spin.setDecimals(0)
        self.lead_spin.setSuffix(" ms")
        self.lead_spin.setKeyboardTracking(False)  # one reopen when the value is committed
        self.lead_spin.setValue(device.lead_ms)
        self._in_use: set = {None}
        """What in the device box means the link in use (None: the simulated array)."""
        self.status_label = ElidedLabel("starting")  # one line; the whole of it as the tooltip
        self.status_label.setObjectName("status")
        self.felt_label = ElidedLabel("felt: computing")  # the setting's cost in felt terms
        self.felt_label.setObjectName("felt_cost")
        self.felt_cost = FeltCost(device, self)
        self.felt_cost.changed.connect(self._on_felt_cost_changed)
        layout.addWidget(QtWidgets.QLabel("device"), 0, 0)
        layout.addWidget(self.port_combo, 0, 1)
        layout.addWidget(self.refresh_button, 0, 2)
        layout.addWidget(self.connect_button, 0, 3)
        layout.addWidget(self.disconnect_button, 0, 4)
        layout.addWidget(QtWidgets.QLabel("profile"), 1, 0)
        profile_row = QtWidgets.QHBoxLayout()
        profile_row.addWidget(self.profile_combo)
        profile_row.addWidget(self.profile_label, 1)
        layout.addLayout(profile_row, 1, 1)
        layout.addWidget(self.profile_button, 1, 2)
        self.lead_spin.setPrefix("lead ")
        layout.addWidget(self.lead_spin, 1, 3)
        layout.addWidget(self.link_label, 1, 4)
        layout.addWidget(self.status_label, 2, 0, 1, 5)
        layout.addWidget(self.felt_label, 3, 0, 1, 5)
        layout.setColumnStretch(1, 1)
        self.port_combo.setToolTip(tip(
            "A serial port or any pyserial URL (/dev/ttyUSB0, COM3, socket://host:port, "
            "rfc2217://..., spy://...); an audio interface, one channel per actuator "
            "(audio:NAME, audio:NAME?carrier_hz=170); sim for the built-in simulated array. "
            "Enter connects."
        ))  # fmt: skip
        self.connect_button.setToolTip(tip("Stream to the device; it is asked who it is first"))
        self.profile_button.setToolTip(tip("Load a device profile from a file (grid or actuator "
                                           "layout, levels, baud, channel order, calibration, "
                                           "motor response)"))  # fmt: skip
        self.profile_combo.setToolTip(tip(
            "The array's device profile: the paper's palm array, a 3 x 3 grid, a belt, a sleeve, "
            "a vest panel, or your own (in ~/.config/tactile-tuner/devices). The views and the "
            "methods follow its layout"
        ))  # fmt: skip
        self.lead_spin.setToolTip(tip(
            "Send frames this far ahead, to be played at their time by the array's own clock "
            "(arrays with scheduled frames; others play frames on arrival). Longer: the host's "
            "stutters never reach the skin; shorter: a change is felt sooner. 20 ms kept every "
            "frame on time with both cores busy (docs: Benchmarks, the lead against latency)"
        ))  # fmt: skip
        self.lead_spin.valueChanged.connect(self._on_lead_changed)
        self.port_combo.lineEdit().returnPressed.connect(self._on_connect_clicked)
        self.port_combo.currentTextChanged.connect(lambda _: self._update_connect())
        self.refresh_button.clicked.connect(lambda: self.refresh_ports())
        self.connect_button.clicked.connect(self._on_connect_clicked)
        self.disconnect_button.clicked.connect(device.disconnect_device)
        self.profile_button.clicked.connect(self.profile_requested.emit)
        self.profile_combo.activated.connect(self._on_profile_combo_activated)
        device.connection_changed.connect(self._on_device_connection_changed)
        device.status_changed.connect(self.show_stats)
        self._timer = QtCore.QTimer(self)
        self._timer.timeout.connect(lambda: self.show_stats(device.stats))
        self._timer.start(500)
        self.refresh_ports(rescan=False)  # PortAudio has just looked
        self._on_device_connection_changed(device.description)

    def refresh_ports(self, rescan: bool = True) -> None:
        """List the simulated array, serial ports (``serial.tools.list_ports``) and audio
        output devices (``audio:NAME``, what they offer as the item's tip)."""
        current = self.port_combo.currentText()
        self.port_combo.clear()
        self.port_combo.addItem("sim")
        for port in sorted(list_ports.comports(), key=lambda p: p.device):
            label = f"{port.device}"
            self.port_combo.addItem(label)
        for url, label in audio_outputs(rescan=rescan):
            self.port_combo.addItem(url)
            index = self.port_combo.count() - 1
            self.port_combo.setItemData(index, label, QtCore.Qt.ItemDataRole.ToolTipRole)
        if current:
            self.port_combo.setCurrentText(current)

    def _fill_profiles(self) -> None:
        """The known profiles by name, the one in use selected (added if it came from a file)."""
        combo, current = self.profile_combo, self.device.profile.name
        combo.blockSignals(True)
        combo.clear()
        names = list(profile_names())
        for name in names:
            combo.addItem(name, name)
        if current not in names:
            combo.addItem(f"{current} (file)", None)
        combo.setCurrentIndex(names.index(current) if current in names else combo.count() - 1)
        combo.blockSignals(False)

    def _on_profile_combo_activated(self, index: int) -> None:
        name = self.profile_combo.itemData(index)
        if name is not None and name != self.device.profile.name:
            self.profile_chosen.emit(name)
        self._fill_profiles()  # what is in use (a refused change leaves the profile as it was)

    def _on_felt_cost_changed(self, text: str, tooltip: str) -> None:
        self.felt_label.setText(text)
        self.felt_label.setToolTip(tooltip)

    def set_status_visible(self, visible: bool) -> None:
        """The status line and the felt read-out, hidden while they would give a stimulus away
        (a blind test, an experiment run); hidden, the read-out is not computed."""
        self.status_label.setVisible(visible)
        self.felt_label.setVisible(visible)
        self.felt_cost.set_enabled(visible)

    def _on_lead_changed(self, value: float) -> None:
        if not self.device.set_lead(value):
            self.lead_spin.blockSignals(True)
            self.lead_spin.setValue(self.device.lead_ms)
            self.lead_spin.blockSignals(False)

    def _typed_link(self) -> str | None:
        """The link the box names: a port or URL, None for the simulated array."""
        text = self.port_combo.currentText().strip()
        return None if text in ("", *SIMULATED_URLS) else text

    def _update_connect(self) -> None:
        """Connect only for a link other than the one in use (its own port would be busy)."""
        self.connect_button.setEnabled(self._typed_link() not in self._in_use)

    def _on_connect_clicked(self) -> None:
        if self._typed_link() in self._in_use:
            return  # already streaming there (Enter again, a double click)
        if not self.device.connect_device(self.port_combo.currentText()):
            # Refused (the message names the link typed): the box shows the link in use again,
            # not one that plays nothing while the simulated array goes on.
            self.port_combo.setCurrentText(self._link_in_use()[0])

    def set_run_locked(self, locked: bool) -> None:
        """During an experiment run the device stays as it is: another port, a disconnect
        (the simulated array took over without a word) or a new lead (the stream restarts and
        its counters with it) would change what the trials record."""
        for widget in (self.port_combo, self.refresh_button, self.connect_button,
                       self.lead_spin):  # fmt: skip
            widget.setEnabled(not locked)
        self.disconnect_button.setEnabled(not locked and not self.device.simulated)

    def _on_device_connection_changed(self, description: str) -> None:
        profile = self.device.profile
        self._fill_profiles()
        self.profile_label.setText(
            f"{profile.layout.describe()}, {profile.levels} levels, {profile.baud} baud (max "
            f"{profile.max_rate_hz:.0f} frames/s)"
        )
        self.profile_label.setToolTip(
            tip(f"{self.profile_label.text()}. {profile.description or profile.name}")
        )
        shown, label = self._link_in_use()
        self.port_combo.setCurrentText(shown)  # the link in use, named (it said "sim" for all)
        self.link_label.setText(f"<b>{html.escape(description if label is None else shown)}</b>")
        self.link_label.setToolTip(tip(label or description))
        self.disconnect_button.setEnabled(not self.device.simulated)
        self.lead_spin.blockSignals(True)  # a preset may have set another lead
        self.lead_spin.setValue(self.device.lead_ms)
        self.lead_spin.blockSignals(False)
        self._update_connect()

    def _link_in_use(self) -> tuple[str, str | None]:
        """What the device box shows for the link in use, and an audio device's description:
        ``sim``; a port or URL as given; an ``audio:`` URL as the device it opened
        (``audio:`` is the default device: ``audio:USB 8ch``, its query kept)."""
        url = self.device.url
        if url is None:
            self._in_use = {None}
            return "sim", None
        named = audio_output_of(url)
        if named is None:
            self._in_use = {url}
            return url, None
        query = url.partition("?")[2]
        shown = named[0] + (f"?{query}" if query else "")
        self._in_use = {url, shown}
        return shown, named[1]

    def show_stats(self, stats) -> None:
        """Status line: state, what plays (the stream's method, or a pulse: ``pulsing tactor
        (2,3) (CT) at 300 Hz``), achieved rate, interval error, errors; and how frames are timed
        (also the lead box's status tip)."""
        self.lead_spin.setStatusTip(stats.schedule)
        status, apart = stats.status, self.device.playing_apart
        if apart:  # a pulse: what plays in words, not its method ("streaming CT" under MM)
            status = re.sub(r"^streaming \S+", apart, status)
        self.status_label.setText(
            f"[{stats.state}] {status} | achieved {stats.achieved_rate_hz:.0f} Hz, "
            f"interval error p99 {stats.interval_error_p99_ms:.2f} ms, late {stats.late}, "
            f"errors {stats.errors}, {stats.frames} frames"
            + (f" | timed {stats.lead_ms:g} ms ahead" if stats.scheduled else " | frames for now")
        )
