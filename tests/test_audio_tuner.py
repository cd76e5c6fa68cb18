"""The tuner's device box with audio interfaces (on the stand-in for sounddevice): listed beside
the serial ports as ``audio:NAME``, connected to, streamed to, and let go of in silence."""

import numpy as np
import pytest
from PySide6 import QtCore

from tactile_core.device.profile import default_profile, profile_from_dict

from .audio_fake import card, fake_audio

pytestmark = pytest.mark.usefixtures("qt_settings")


def eight_channels():
    data = default_profile().to_dict()
    data.update(name="belt-8", columns=8, rows=1, carrier_hz=170)
    return profile_from_dict(data)


def test_the_device_box_lists_audio_devices_and_streams_to_one(qtbot, monkeypatch):
    from tactile_tuner.device import DeviceController
    from tactile_tuner.device_panel import DevicePanel
    from tactile_tuner.state import TunerState

    sd, _ = fake_audio(monkeypatch, devices=[card("USB 8ch", 8), card("Speakers", 2, 44100)])
    import tactile_core as tc

    state = TunerState()
    state.update(shape=tc.Line((0.5, 0.5), (7.5, 0.5)), mu=1.0, pause_s=0.0, playing=True)
    # frames for now: the stand-in's stream runs in virtual time, the streamer in real time
    device = DeviceController(state, eight_channels(), process=False, realtime=False, lead_ms=0)
    panel = DevicePanel(device)
    qtbot.addWidget(panel)
    combo = panel.port_combo
    items = [combo.itemText(i) for i in range(combo.count())]
    assert items[0] == "sim" and items[-2:] == ["audio:USB 8ch", "audio:Speakers"]
    tip = combo.itemData(len(items) - 2, QtCore.Qt.ItemDataRole.ToolTipRole)
    assert tip == "USB 8ch (ALSA, 8 channels, 48000 Hz)"
    errors = []
    device.error_raised.connect(errors.append)
    assert not device.connect_device("audio:Speakers")  # 2 channels for 8 actuators
    assert "has 2 output channels: channels=8 (the 8 actuators of the profile belt-8)" in errors[0]
    assert device.connect_device("audio:USB 8ch"), errors
    stream = sd.streams[-1]
    qtbot.waitUntil(lambda: device.stats.frames > 10, timeout=5000)
    stream.pump(4)
    assert np.abs(stream.played()[-256:]).max() > 0  # the scene plays
    device.disconnect_device()
    assert device.simulated and stream.stopped_by == "stop"
    assert not stream.played()[-512:].any()  # let go of in silence
    device.shutdown()


def test_the_device_box_names_the_audio_device_in_use_and_enables_what_applies(qtbot, monkeypatch):
    # Started with --device audio: the box said "sim" and both Connect and Disconnect were on.
    from tactile_tuner.window import MainWindow

    fake_audio(monkeypatch, devices=[card("Speakers", 2, 44100), card("USB 32ch", 32)],
               default_output=1)  # fmt: skip
    win = MainWindow(device_url="audio:", restore=False, process=False)
    qtbot.addWidget(win)
    panel = win.device_panel
    try:
        assert win.device.url == "audio:"
        assert panel.port_combo.currentText() == "audio:USB 32ch"
        assert "USB 32ch" in panel.link_label.text()
        assert "USB 32ch (ALSA, 32 channels, 48000 Hz)" in panel.link_label.toolTip()
        assert not panel.connect_button.isEnabled() and panel.disconnect_button.isEnabled()
        panel.port_combo.setCurrentText("audio:")  # the same device, as it was asked for
        assert not panel.connect_button.isEnabled()
        panel.port_combo.setCurrentText("audio:Speakers")
        assert panel.connect_button.isEnabled()
        panel.disconnect_button.click()
        assert win.device.simulated and panel.port_combo.currentText() == "sim"
        assert not panel.connect_button.isEnabled() and not panel.disconnect_button.isEnabled()
    finally:
        win.close()
