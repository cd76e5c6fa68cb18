"""The Experiments tab's console and the participant's window: who sees what, a run that
refuses to start, a lost link, a full disk, a bad rating, and tuning the correction by feel."""

from PySide6 import QtCore, QtWidgets

import tactile_core as tc

from . import experiments_gui_support as support
from .experiments_gui_support import choose, press, rows, wait_trial

quick_runs = support.quick_runs  # autouse: no pause between questions
quick_tuning = support.quick_tuning
window = support.window


def test_participant_window_shows_only_the_prompt_and_the_console_the_run(window, qtbot):
    panel = window.experiments
    choose(panel, "exp2")
    assert panel.start()
    pw = panel.participant_window
    assert pw.isVisible() and pw is not window
    widgets = pw.findChildren(QtWidgets.QWidget)
    assert {type(w).__name__ for w in widgets} <= {"QLabel", "QLineEdit"}  # nothing to set up
    assert "Experiment 2" in pw.prompt.text()
    assert panel.participant_label.text() == "participant P01"
    assert panel.participant_label.font().pointSize() >= panel.font().pointSize() + 10
    press(qtbot, window, QtCore.Qt.Key.Key_G)
    wait_trial(qtbot, panel, "direction")
    assert "trial 2 of 124" in panel.run_label.text() and "length 2" in panel.run_label.text()
    assert "length" not in pw.prompt.text()  # the stimulus stays off the participant's screen
    assert "participant-P01" in panel.path_label.text()
    qtbot.waitUntil(lambda: "Hz" in panel.health_label.text(), timeout=2000)
    panel.stop()
    assert not pw.isVisible()


def test_the_participant_id_is_required(window):
    panel = window.experiments
    panel.setup.participant_edit.setText("")
    assert not panel.start()
    assert "participant must be" in window.last_error


def test_resuming_an_existing_participant_asks_first(window, qtbot):
    panel = window.experiments
    choose(panel, "exp3")
    asked = []
    panel.confirm = lambda title, text: asked.append(text) or True
    assert panel.start() and "new participant, P01" in asked[-1]
    panel.stop()
    panel.confirm = lambda title, text: asked.append(text) or False
    assert not panel.start() and not panel.running
    assert "P01 already has results" in asked[-1]


def test_a_run_refuses_to_start_while_the_array_is_disconnected(window):
    from tactile_core.stream.streamer import StreamStats

    panel = window.experiments
    panel.stats = lambda: StreamStats(state="disconnected", status="device disconnected: /dev/x")
    assert not panel.start() and not panel.running
    assert "not connected" in window.last_error and "/dev/x" in window.last_error


def test_a_lost_link_pauses_the_run_and_the_trial_is_presented_again(window, qtbot, tmp_path):
    from tactile_core.stream.streamer import StreamStats

    panel = window.experiments
    choose(panel, "exp3")
    panel.start()
    press(qtbot, window, QtCore.Qt.Key.Key_G)
    wait_trial(qtbot, panel, "shape")
    trial = panel.runner.current
    panel.on_device_status(StreamStats(state="disconnected", status="device disconnected"))
    assert not window.state.scene.playing  # the array is off
    assert "link lost" in panel.log.toPlainText()
    assert not panel.trials.submit(trial.info["shape"])  # no answers while the link is down
    panel.on_device_status(StreamStats(state="streaming", status="reconnected"))
    assert "back" in panel.log.toPlainText() and panel.setup.resume_button.isEnabled()
    press(qtbot, window, QtCore.Qt.Key.Key_Return)
    assert panel.runner.current == trial and window.state.scene.playing
    press(
        qtbot,
        window,
        QtCore.Qt.Key.Key_C if trial.info["shape"] == "circle" else QtCore.Qt.Key.Key_S,
    )
    panel.stop()
    data = rows(tmp_path / "results" / "participant-P01" / "exp3.csv")
    assert data[-1]["presentations"] == "2"  # marked: presented twice
    assert data[-2]["presentations"] == "1"


def test_a_real_link_drop_reaches_the_run(window, qtbot, emulator_thread):
    emulator, path = emulator_thread
    window.device_panel.port_combo.setCurrentText(path)
    qtbot.mouseClick(window.device_panel.connect_button, QtCore.Qt.MouseButton.LeftButton)
    panel = window.experiments
    choose(panel, "exp3")
    panel.start()
    press(qtbot, window, QtCore.Qt.Key.Key_G)
    wait_trial(qtbot, panel, "shape")
    emulator.unplugged = True
    qtbot.waitUntil(lambda: "link lost" in panel.log.toPlainText(), timeout=5000)
    assert panel.trials.paused and not window.state.scene.playing


def test_a_run_restores_the_tuning_scene_and_never_writes_settings(window, qtbot):
    tuning = window.state.scene.replace(shape=tc.Circle((2.0, 3.0), 1.5), mu=0.5, method="IM")
    window.state.set_scene(tuning)
    before = window.settings.value("scene")
    panel = window.experiments
    choose(panel, "exp3")
    panel.start()
    press(qtbot, window, QtCore.Qt.Key.Key_G)
    wait_trial(qtbot, panel, "shape")
    assert window.state.scene.shape != tuning.shape  # the trial plays
    window.save_settings()  # e.g. the window closed mid-run
    saved = window.settings.value("scene")
    assert '"mu": 0.5' in saved and '"radius": 1.5' in saved  # the tuning scene, not the trial's
    panel.stop()
    scene = window.state.scene
    assert (scene.shape, scene.mu, scene.method) == (tuning.shape, tuning.mu, tuning.method)
    assert not scene.playing  # restored paused: a hand may still be on the array
    del before


def test_an_invalid_rating_is_refused_visibly(window, qtbot):
    panel = window.experiments
    choose(panel, "exp1")
    panel.start()
    press(qtbot, window, QtCore.Qt.Key.Key_R)
    assert panel.runner.current.kind == "rating"
    done = panel.runner.done
    for text in ("150", "-3", "abc"):
        panel.participant_window.rating_edit.setText(text)
        qtbot.keyClick(panel.participant_window.rating_edit, QtCore.Qt.Key.Key_Return)
        assert "0 to 100" in panel.participant_window.rating_error.text()
        assert panel.runner.done == done
    panel.participant_window.rating_edit.setText("100")
    qtbot.keyClick(panel.participant_window.rating_edit, QtCore.Qt.Key.Key_Return)
    assert panel.runner.done == done + 1 and panel.participant_window.rating_error.text() == ""


def test_a_full_disk_keeps_the_trial_on_screen(window, qtbot, monkeypatch):
    import errno

    panel = window.experiments
    choose(panel, "exp3")
    panel.start()
    press(qtbot, window, QtCore.Qt.Key.Key_G)
    wait_trial(qtbot, panel, "shape")
    trial = panel.runner.current

    def full(row):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(panel.runner._file, "append", full)
    assert not panel.trials.submit("circle")
    assert panel.runner.current == trial and "No space" in window.last_error
    monkeypatch.undo()
    assert panel.trials.submit("circle")
    assert panel.runner.done == 2


def test_tune_by_feel_guides_plays_two_intervals_and_applies_the_result(
    window, qtbot, quick_tuning, tmp_path
):
    from tactile_core.experiments.tuning import SimulatedObserver

    panel = window.experiments
    trials = panel.trials
    window.start_tuning()
    assert window.tabs.currentWidget() is panel
    assert panel.setup.experiment_combo.currentData() == "correction"
    assert "mu, then gamma" in panel.run_label.text() and "Esc pauses" in panel.run_label.text()
    assert panel.start()
    Key = QtCore.Qt.Key
    press(qtbot, window, Key.Key_G)  # the instructions
    trial = panel.runner.current
    assert trial.kind == "interval"
    # Interval 1 plays first: the array plays it (or is silent), then interval 2, then the
    # question; a key pressed before both have played is not taken.
    first = trial.intervals[0]
    if first is None:
        assert not window.state.scene.playing
    else:
        assert window.state.scene.shape == first.shape and window.state.scene.gain == first.gain
    assert panel.trials.intervals_playing
    press(qtbot, window, Key.Key_1)
    assert panel.runner.done == 1  # only the instructions so far
    observer = SimulatedObserver(0.3, 1.0, seed=4)
    while panel.runner is not None:
        qtbot.waitUntil(lambda: not trials.intervals_playing and not trials.gap_timer.isActive(),
                        timeout=3000)  # fmt: skip
        if panel.runner is None:  # the last answer finished the run
            break
        trial = panel.runner.current
        if trial.kind == "continue":
            press(qtbot, window, Key.Key_G)
            continue
        answer = observer.respond(trial)
        press(qtbot, window, Key.Key_1 if answer == "1" else Key.Key_2)
    result = panel.last_tuning
    assert result is not None and result.ok, result.message
    folder = tmp_path / "results" / "participant-P01"
    assert (folder / "correction.json").exists() and (folder / "correction-P01.json").exists()
    assert len(rows(folder / "correction.csv")) == 2 + 5 * 12 + 2 * 16 + 4
    dialog = window.guided.dialog
    assert f"{result.mu:.3f}" in dialog.findChild(QtWidgets.QPlainTextEdit).toPlainText()
    dialog.apply_button.click()
    assert (window.state.scene.mu, window.state.scene.gamma) == (result.mu, result.gamma)
    assert panel.analysis.save_profile_button.isEnabled()  # the thresholds feed the calibration


def test_escape_while_the_intervals_play_pauses_with_the_array_off(window, qtbot, quick_tuning):
    panel = window.experiments
    choose(panel, "correction")
    assert panel.start()
    press(qtbot, window, QtCore.Qt.Key.Key_G)
    assert panel.trials.intervals_playing
    qtbot.keyClick(window.experiments.participant_window.prompt, QtCore.Qt.Key.Key_Escape)
    assert not panel.trials.intervals_playing and not window.state.scene.playing
    assert not panel.trials.interval_timer.isActive()  # nothing is timed to play interval 2
    QtWidgets.QApplication.processEvents()  # nor posted to
    assert not window.state.scene.playing
    panel.trials.present_again()
    assert panel.trials.intervals_playing
