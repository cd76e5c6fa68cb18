"""LSL in the tuner: the marker outlet opened from the Array menu lives in the stream process, and
each presentation (here a Blind A/B play) is one marker stamped with its first frame's send time,
which the stream process also forwards to the tuner with each onset; scenes carry their kind."""

import json
import time
import uuid

import pytest

from .test_lsl import inlet_for, own_offset

pytestmark = pytest.mark.usefixtures("qt_settings")
WAIT_MS = 15_000


@pytest.fixture
def window(qtbot):
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False)  # the stream process, as in use
    qtbot.addWidget(win)
    win.resize(1280, 720)
    win.show()
    qtbot.waitExposed(win)
    qtbot.waitUntil(lambda: win.device.stats.frames > 5, timeout=WAIT_MS)
    yield win
    win.close()


def ab_onsets(onsets):
    return [o for o in onsets if o.scene is not None and o.scene.marker == "ab" and o.cycle == 0]


def test_tuner_lsl_marks_each_blind_ab_play_at_its_first_frames_send_time(qtbot, window):
    sid = f"test-{uuid.uuid4().hex}"
    window.serve.lsl_source_id = sid
    onsets = []  # forwarded by the stream process, with the first frame's send time
    window.device.streamer.on_onset.append(onsets.append)
    window.findChild(type(window.menuBar().actions()[0]), "lsl_action").trigger()
    qtbot.waitUntil(lambda: window.serve.lsl_status == f"{sid}-markers", timeout=WAIT_MS)
    assert "LSL markers: " + sid in window.serve_panel.lsl_label.text()
    inlet, info = inlet_for(f"source_id='{sid}-markers'")
    assert (info.name(), info.type()) == ("tactile-markers", "Markers")
    offset = own_offset()
    assert window.blind.start(seed=5)  # plays nothing until a key
    window.blind.select_key(1)
    qtbot.waitUntil(lambda: len(ab_onsets(onsets)) == 1, timeout=WAIT_MS)
    window.blind.select_key(2)
    qtbot.waitUntil(lambda: len(ab_onsets(onsets)) == 2, timeout=WAIT_MS)
    plays = ab_onsets(onsets)
    markers = []
    deadline = time.monotonic() + 15

    def first_cycles():  # key 1 plays again after 2.5 s: its second cycle is not a play
        return [m for m, _ in markers if m["kind"] == "ab" and m["cycle"] == 0]

    while len(first_cycles()) < 2 and time.monotonic() < deadline:
        sample, stamp = inlet.pull_sample(timeout=0.5)
        if sample is not None:
            markers.append((json.loads(sample[0]), stamp))
    inlet.close_stream()
    ab = [(m, stamp) for m, stamp in markers if m["kind"] == "ab" and m["cycle"] == 0]
    assert len(ab) == 2, markers  # one per play
    for (marker, stamp), onset in zip(ab, plays):
        assert marker["seq"] == onset.seq
        assert marker["method"] == onset.scene.method
        assert abs(stamp - offset - onset.time_s) < 1e-3
    assert [m["method"] for m, _ in ab] == list(window.blind.session.mapping[:2])
    window.serve.set_lsl(False)
    qtbot.waitUntil(lambda: window.serve.lsl_status == "off", timeout=WAIT_MS)


def test_tuner_scenes_carry_their_presentation_kind(qtbot, window):
    state, device = window.state, window.device
    assert state.scene.marker == "" and device.streamer.scene.marker == "tune"
    window.blind.start(seed=1)
    window.blind.select_key(1)  # Start plays nothing: the rater's first key does
    assert state.scene.marker == "ab" and device.streamer.scene.marker == "ab"
    epoch = state.scene.epoch
    window.blind.select_key(2)
    assert state.scene.epoch == epoch + 1  # a play starts the trace again: its own onset
    state.update(mu=0.2)  # the same presentation
    assert device.streamer.scene.marker == "ab"
    window.blind.cancel()
    state.restart()  # a new presentation of the tuner's own
    assert state.scene.marker == "" and device.streamer.scene.marker == "tune"
    trials = window.experiments.trials
    trials._play(state.scene.replace(epoch=0), "interval")
    assert device.streamer.scene.marker == "interval"
    trials._play(state.scene)
    assert device.streamer.scene.marker == "trial"


def test_tuner_lsl_levels_outlet_carries_the_frames(qtbot):
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False, process=False)
    qtbot.addWidget(win)
    try:
        sid = f"test-{uuid.uuid4().hex}"
        win.serve.lsl_source_id = sid
        win.serve.set_lsl(True, levels=True)
        qtbot.waitUntil(lambda: win.serve.lsl_status == f"{sid}-markers", timeout=WAIT_MS)
        assert "LSL markers and levels" in win.serve_panel.lsl_label.text()
        inlet, info = inlet_for(f"source_id='{sid}-levels'")
        assert info.channel_count() == win.device.profile.channels
        sample, _ = inlet.pull_sample(timeout=10)
        assert sample is not None and len(sample) == 30 and max(sample) <= 22
        inlet.close_stream()
    finally:
        win.close()
