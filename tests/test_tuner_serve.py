"""The tuner driven by another program: the OSC server runs in the stream process, an OSC client
(python-osc) on loopback moves the point, the tuner's method, mu and gamma apply to it, the
counters show, and turning it off, closing the window or losing the stream process releases the
port and leaves the array off."""

import math
import socket

import numpy as np
import pytest
from pythonosc.udp_client import SimpleUDPClient

import tactile_core as tc

pytestmark = pytest.mark.usefixtures("qt_settings")
WAIT_MS = 15_000


def make_window(qtbot, process=True):
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False, process=process)
    qtbot.addWidget(win)
    win.resize(1280, 720)
    win.show()
    qtbot.waitExposed(win)
    qtbot.waitUntil(lambda: win.device.stats.frames > 5, timeout=WAIT_MS)
    return win


@pytest.fixture
def clients():
    """OSC clients, closed after the test."""
    made = []
    yield made
    for client in made:
        client.close()


def serve(qtbot, win, clients):
    """Turn the server on with the device dock's button, on a free port; a client."""
    panel = win.serve_panel
    panel.port_spin.setValue(0)
    panel.toggle.click()
    qtbot.waitUntil(lambda: win.serve.serving == "on", timeout=WAIT_MS)
    assert panel.toggle.isChecked() and not panel.port_spin.isEnabled()
    host, port = win.serve.address
    assert host == "127.0.0.1" and port > 0
    clients.append(SimpleUDPClient(host, port))
    return clients[-1], port


def port_free(port):
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    try:
        sock.bind(("127.0.0.1", port))
    except OSError:
        return False
    finally:
        sock.close()
    return True


def until_sent(qtbot, osc, point, predicate):
    """Send ``point`` again and again (it times out after 100 ms) until ``predicate()``."""

    def check():
        osc.send_message("/tactile/point", list(point))
        return predicate()

    qtbot.waitUntil(check, timeout=WAIT_MS)


def levels_of(mu, gamma, value=0.5):
    return int(tc.quantize(tc.correct(np.array([value]), mu=mu, gamma=gamma), 23)[0])


def test_tuner_serves_osc_from_the_stream_process_and_its_controls_tune_the_point(qtbot, clients):
    win = make_window(qtbot)
    try:
        state, device = win.state, win.device
        state.update(method="AS", mu=0.33, gamma=0.7)
        osc, port = serve(qtbot, win, clients)
        # AS halfway between tactors (0, 0) and (1, 0): each gets 0.5, corrected by mu, gamma.
        expected = levels_of(0.33, 0.7)

        def halfway(levels):  # one snapshot: the stream publishes a newer one every 10 ms
            return levels[0, 0] == levels[0, 1] == expected and levels[1:].sum() == 0

        until_sent(qtbot, osc, (1.0, 0.5), lambda: halfway(device.sent_levels()))
        # The heatmap shows the stream's frames (in every view but felt) and the driven point.
        heatmap = win.tune.heatmap
        until_sent(qtbot, osc, (1.0, 0.5), lambda: heatmap.values[0, 0] > 0.6
                   and heatmap.point_xy == pytest.approx((1.0, 0.5)))  # fmt: skip
        # The tuner's sliders apply to the driven point.
        win.controls.correction.mu_spin.setValue(0.0)
        win.controls.correction.gamma_spin.setValue(1.0)
        until_sent(qtbot, osc, (1.0, 0.5), lambda: device.sent_levels()[0, 0] == levels_of(0, 1))
        # A sender's /tactile/mu moves the tuner's control.
        osc.send_message("/tactile/mu", 0.25)
        qtbot.waitUntil(lambda: math.isclose(state.scene.mu, 0.25, abs_tol=1e-6),
                        timeout=WAIT_MS)  # fmt: skip
        assert win.controls.correction.mu_spin.value() == pytest.approx(0.25)
        until_sent(qtbot, osc, (1.0, 0.5), lambda: device.sent_levels()[0, 0] == levels_of(0.25, 1))
        # A method that needs a shape is refused, in the status line.
        assert win.press_number(4)  # IM
        assert state.scene.method == "AS"
        assert "needs a shape" in win.statusBar().currentMessage()
        # The counters.
        raw = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        raw.sendto(b"not osc", ("127.0.0.1", port))
        raw.close()
        osc.send_message("/tactile/nowhere", 1)
        osc.send_message("/tactile/point", [math.nan, 1.0])
        text = win.serve_panel.counters.text
        qtbot.waitUntil(lambda: "malformed 1" in text() and "unknown 1" in text()
                        and "non-finite 1" in text(), timeout=WAIT_MS)  # fmt: skip
        traffic = win.serve_panel.traffic.text()
        assert f"udp 127.0.0.1:{port}" in traffic and "last sender 127.0.0.1:" in traffic
        qtbot.waitUntil(lambda: "released by timeout 0" not in text(), timeout=WAIT_MS)
        # Off: the port is released, the array all off and the tuner paused.
        win.serve_panel.toggle.click()
        assert win.serve.serving == "off" and not state.scene.playing
        qtbot.waitUntil(lambda: port_free(port), timeout=WAIT_MS)
        osc.send_message("/tactile/point", [2.5, 3.0])
        qtbot.waitUntil(lambda: device.sent_levels().sum() == 0, timeout=WAIT_MS)
        assert device.streamer.running
    finally:
        win.close()


def test_tuner_serve_closes_with_the_window_and_when_the_stream_process_dies(qtbot, clients):
    win = make_window(qtbot)
    _, port = serve(qtbot, win, clients)
    child = win.device.streamer._proc
    child.kill()
    qtbot.waitUntil(lambda: win.serve.serving == "off", timeout=WAIT_MS)
    assert not win.serve_panel.toggle.isChecked()
    assert "OSC server is off" in win.statusBar().currentMessage()
    qtbot.waitUntil(lambda: port_free(port), timeout=WAIT_MS)
    win.close()

    win = make_window(qtbot)
    _, port = serve(qtbot, win, clients)
    child = win.device.streamer._proc
    win.close()
    assert child.poll() is not None and port_free(port)


def test_tuner_serve_in_process_stream_and_blind_ab_turns_it_off(qtbot, clients):
    win = make_window(qtbot, process=False)
    try:
        osc, port = serve(qtbot, win, clients)
        levels = win.device.sent_levels
        until_sent(qtbot, osc, (0.5, 0.5), lambda: levels()[0, 0] == 22)
        im = win.controls.method.method_buttons.button(3)
        assert not im.isEnabled()  # MM and IM need a shape
        win.state.set_scene(win.state.scene.replace(method="IM"))  # a preset's: refused too
        qtbot.waitUntil(lambda: win.state.scene.method == "AS", timeout=WAIT_MS)
        win.toggle_play()  # Space: the points pause, all off
        until_sent(qtbot, osc, (0.5, 0.5), lambda: levels().sum() == 0)
        win.toggle_play()
        until_sent(qtbot, osc, (0.5, 0.5), lambda: levels()[0, 0] == 22)
        said = []
        win.serve.message_posted.connect(lambda text, _ms: said.append(text))
        assert win.blind.start(seed=1)
        assert win.serve.serving == "off" and "Blind A/B session plays" in said[0]
        qtbot.waitUntil(lambda: port_free(port), timeout=WAIT_MS)
        win.serve_panel.toggle.click()  # refused while blind
        assert win.serve.serving == "off" and not win.serve_panel.toggle.isChecked()
        assert "cannot run during a Blind A/B session" in said[-1]
        win.blind.cancel()
        assert im.isEnabled()
    finally:
        win.close()


def test_tuner_serve_bad_address_is_refused_and_the_tuner_plays_on(qtbot, clients):
    win = make_window(qtbot, process=False)
    busy = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    busy.bind(("127.0.0.1", 0))
    try:
        win.serve_panel.port_spin.setValue(busy.getsockname()[1])
        win.serve_panel.toggle.click()
        qtbot.waitUntil(lambda: win.serve.serving == "off", timeout=WAIT_MS)
        assert "could not start" in win.last_error and "in use" in win.last_error
        assert win.device.divert is None and not win.serve_panel.toggle.isChecked()
        win.serve_panel.host_edit.setText("0.0.0.0")
        assert win.serve_panel.warning.isVisibleTo(win.serve_panel)
    finally:
        busy.close()
        win.close()


def test_tuner_remembers_the_lsl_setting_and_the_osc_address(qtbot):
    from tactile_tuner.settings import restore_serve

    win = make_window(qtbot, process=False)
    try:
        win.serve_panel.port_spin.setValue(9123)
        win.findChild(type(win.menuBar().actions()[0]), "lsl_action").trigger()
        qtbot.waitUntil(lambda: win.serve.lsl_status.endswith("-markers"), timeout=WAIT_MS)
        win.save_settings()
        win.serve.set_lsl(False)
        assert win.serve.lsl_status == "off"
        win.serve.port = 1
        restore_serve(win.settings, win.serve)
        assert win.serve.lsl_markers and win.serve.port == 9123
        assert "LSL markers" in win.serve_panel.lsl_label.text()
    finally:
        win.close()


def test_tuner_serve_comes_back_on_the_same_port_with_another_stream(qtbot, clients):
    win = make_window(qtbot, process=False)
    try:
        win.state.update(playing=False)
        osc, port = serve(qtbot, win, clients)
        assert win.state.scene.playing  # the sender's points play at once
        win.device_panel.lead_spin.setValue(0)  # the stream reopens
        qtbot.waitUntil(lambda: win.serve.serving == "on", timeout=WAIT_MS)
        assert win.serve.address == ("127.0.0.1", port) and win.device.lead_ms == 0
        until_sent(qtbot, osc, (4.5, 5.5), lambda: win.device.sent_levels()[5, 4] == 22)
    finally:
        win.close()
    assert port_free(port)


def test_a_senders_mu_marks_the_scene_modified_in_the_title(qtbot, clients):
    # The title kept no "modified" star: a tuner started without a last session had no preset
    # to compare the scene with.
    win = make_window(qtbot, process=False)
    try:
        assert "*" not in win.windowTitle()
        osc, _ = serve(qtbot, win, clients)
        osc.send_message("/tactile/mu", 0.25)
        qtbot.waitUntil(lambda: math.isclose(win.state.scene.mu, 0.25, abs_tol=1e-6),
                        timeout=WAIT_MS)  # fmt: skip
        assert "Experiment 1 line * - AS, mu 0.25" in win.windowTitle()
        osc.send_message("/tactile/gamma", 0.142)  # the status said 0.14, the title 0.142
        qtbot.waitUntil(lambda: "gamma" in win.statusBar().currentMessage(), timeout=WAIT_MS)
        assert win.statusBar().currentMessage() == "the sender set mu 0.25, gamma 0.142"
        assert win.windowTitle().endswith("mu 0.25, gamma 0.142")
    finally:
        win.close()


def test_the_status_line_names_every_field_the_sender_set_and_the_boxes_show_them(qtbot, clients):
    # /tactile/mu 0.5 then /tactile/gamma 50: the status line said only "gamma 50.00" (the mu
    # went unsaid), and the gamma box read 10.00, the end of its range, while gamma 50 played.
    win = make_window(qtbot, process=False)
    try:
        osc, _ = serve(qtbot, win, clients)
        osc.send_message("/tactile/mu", 0.5)
        osc.send_message("/tactile/gamma", 50.0)
        osc.send_message("/tactile/method", "CT")
        qtbot.waitUntil(lambda: "CT" in win.statusBar().currentMessage(), timeout=WAIT_MS)
        assert win.statusBar().currentMessage() == (
            "the sender set mu 0.50, gamma 50.00, method CT"
        )
        correction = win.controls.correction
        assert (win.state.scene.mu, win.state.scene.gamma) == (0.5, 50.0)
        assert (correction.mu_spin.text(), correction.gamma_spin.text()) == ("0.50", "50.00")
        assert correction.gamma_slider.value() == correction.gamma_slider.maximum()
        assert win.windowTitle().endswith("CT, mu 0.50, gamma 50.00")
    finally:
        win.close()
