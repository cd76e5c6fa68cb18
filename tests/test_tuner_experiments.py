"""The tuner's Experiments tab, driven from the keyboard against the simulated array."""

import csv
import json

import pytest
from PySide6 import QtCore, QtGui, QtWidgets

import tactile_core as tc


@pytest.fixture(autouse=True)
def quick_runs(qt_settings, monkeypatch):
    import tactile_tuner.experiments

    monkeypatch.setattr(
        tactile_tuner.experiments, "GAP_S", 0.01
    )  # no pause between questions in tests


@pytest.fixture
def window(qtbot, tmp_path):
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False)
    qtbot.addWidget(win)
    win.show()
    qtbot.waitExposed(win)
    panel = win.experiments
    panel.folder_edit.setText(str(tmp_path / "results"))
    panel.participant_edit.setText("P01")
    panel.confirm = lambda title, text: True  # the experimenter says yes
    win.tabs.setCurrentWidget(panel)
    yield win
    panel.stop()
    win.close()


def choose(panel, name):
    panel.experiment_combo.setCurrentIndex(panel.experiment_combo.findData(name))


def press(qtbot, win, key, text=""):
    qtbot.keyClick(win.experiments.prompt, key)


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def wait_trial(qtbot, panel, kind):
    qtbot.waitUntil(
        lambda: panel.runner is not None and panel.runner.current is not None
        and panel.runner.current.kind == kind and not panel.gap_timer.isActive(),
        timeout=3000,
    )  # fmt: skip


def test_experiment3_by_keyboard_hides_the_display_and_records_every_answer(
    window, qtbot, tmp_path
):
    panel = window.experiments
    choose(panel, "exp3")
    assert panel.start()
    assert window.tune_stack.currentIndex() == 1 and not window.tabs.isTabEnabled(0)
    assert not window.controls_dock.isVisible()  # its shape fields would give the answer away
    assert not window.device_panel.status_label.isVisible()  # so would "streaming MM at ..."
    assert "Experiment 3" in panel.prompt.text()
    Key = QtCore.Qt.Key
    answered = 0
    while panel.runner is not None:
        trial = panel.runner.current
        if trial.kind == "continue":
            press(qtbot, window, Key.Key_G)
        else:
            wait_trial(qtbot, panel, "shape")
            trial = panel.runner.current
            # the array plays the trial's stimulus
            assert window.state.scene.shape == trial.scene.shape
            assert window.state.scene.method == trial.info["method"]
            press(qtbot, window, Key.Key_C if trial.info["shape"] == "circle" else Key.Key_S)
            answered += 1
            qtbot.waitUntil(
                lambda: panel.runner is None or not panel.gap_timer.isActive(), timeout=2000
            )
    assert answered == 40
    assert "Finished" in panel.run_label.text() and "finished" in panel.prompt.text()
    assert window.tune_stack.currentIndex() == 0 and window.tabs.isTabEnabled(0)
    assert window.controls_dock.isVisible()
    data = rows(tmp_path / "results" / "participant-P01" / "exp3.csv")
    questions = [r for r in data if r["stage"] in ("CT", "MM", "AS", "IM")]
    assert len(questions) == 40 and all(r["correct"] == "1" for r in questions)
    assert all(float(r["rt_s"]) >= 0 for r in questions)
    assert not window.state.scene.playing  # the array is off at the end


def test_experiment3_time_limit_records_a_timeout(window, qtbot, monkeypatch, tmp_path):
    from tactile_core.experiments import runners

    monkeypatch.setattr(runners.Experiment3, "TIME_LIMIT_S", 0.3)
    panel = window.experiments
    choose(panel, "exp3")
    panel.start()
    press(qtbot, window, QtCore.Qt.Key.Key_G)
    wait_trial(qtbot, panel, "shape")
    assert "s left" in panel.countdown.text()
    qtbot.waitUntil(lambda: panel.runner.done == 2, timeout=3000)  # nobody answered
    assert panel.feedback.text().startswith("Time is up: it was a")
    data = rows(tmp_path / "results" / "participant-P01" / "exp3.csv")
    assert data[-1]["timeout"] == "1" and data[-1]["answer"] == ""


def test_experiment1_preparation_keys_and_ratings_then_stop_and_resume(window, qtbot, tmp_path):
    panel = window.experiments
    choose(panel, "exp1")
    panel.start()
    Key = QtCore.Qt.Key
    mapping = panel.runner.mapping
    for key, qt_key in ((3, Key.Key_3), (1, Key.Key_1), (4, Key.Key_4)):
        press(qtbot, window, qt_key)
        assert window.state.scene.method == mapping[key - 1]  # the hidden mapping plays
    press(qtbot, window, Key.Key_R)  # a letter: on to the ratings
    assert panel.runner.current.kind == "rating" and panel.rating_edit.isVisible()
    for value in ("85", "40"):
        qtbot.keyClicks(panel.rating_edit, value)
        qtbot.keyClick(panel.rating_edit, Key.Key_Return)
    qtbot.keyClicks(panel.rating_edit, "100")
    qtbot.keyClick(panel.rating_edit, Key.Key_Return)
    done = panel.runner.done
    assert done == 4
    panel.stop()
    assert "resume" in panel.run_label.text()
    panel.start()  # the same participant: resumes
    assert panel.runner.done == done and panel.runner.current.kind == "rating"
    data = rows(tmp_path / "results" / "participant-P01" / "exp1.csv")
    assert [r["answer"] for r in data[1:]] == ["85", "40", "100"]
    assert data[0]["mapping"] == " ".join(mapping) and int(data[0]["switches"]) >= 2


def test_experiment1_on_a_chosen_method_set_from_the_console(window, qtbot, tmp_path):
    panel = window.experiments
    choose(panel, "exp1")
    panel.methods_edit.edit.setText("AS EN RO:r=1.5")
    panel.methods_edit.edit.editingFinished.emit()
    assert panel.methods_edit.methods == ["AS", "EN", "RO:r=1.5"]
    assert panel.start()
    Key = QtCore.Qt.Key
    mapping = panel.runner.mapping
    assert sorted(mapping) == ["AS", "EN", "RO:r=1.5"]
    assert "1-3" in panel.keys_label.text()
    press(qtbot, window, Key.Key_3)
    assert window.state.scene.method == mapping[2]
    press(qtbot, window, Key.Key_4)  # no fourth method: nothing changes
    assert window.state.scene.method == mapping[2] and panel.runner.current.kind == "prepare"
    session = json.loads((tmp_path / "results" / "participant-P01" / "session.json").read_text())
    assert session["parameters"]["exp1_methods"] == ["AS", "EN", "RO:r=1.5"]
    # Stopped and resumed with the console back at the paper's four: the participant's own set
    # comes back (a console at its default never overrides what a session recorded).
    panel.stop()
    panel.methods_edit.apply(["CT", "MM", "AS", "IM"])
    assert panel.start()
    assert panel.runner.methods == ["AS", "EN", "RO:r=1.5"]
    assert panel.methods_edit.methods == ["AS", "EN", "RO:r=1.5"]
    panel.stop()
    # A bad set typed into the console is refused on the spot; the last good set stays.
    panel.methods_edit.edit.setText("AS")
    panel.methods_edit.edit.editingFinished.emit()
    assert "choose 2 to 8" in panel.methods_edit.problem.text()
    assert panel.methods_edit.methods == ["AS", "EN", "RO:r=1.5"]


def test_experiment2_arrow_keys_and_feedback(window, qtbot):
    panel = window.experiments
    choose(panel, "exp2")
    panel.start()
    press(qtbot, window, QtCore.Qt.Key.Key_G)
    arrows = {"up": QtCore.Qt.Key.Key_Up, "down": QtCore.Qt.Key.Key_Down,
              "left": QtCore.Qt.Key.Key_Left, "right": QtCore.Qt.Key.Key_Right}  # fmt: skip
    for i in range(6):
        wait_trial(qtbot, panel, "direction")
        trial = panel.runner.current
        assert window.state.scene.method == "AS"
        right = trial.info["direction"]
        answer = right if i % 2 == 0 else next(d for d in arrows if d != right)
        press(qtbot, window, arrows[answer])
        expected = "Correct." if answer == right else f"Wrong: the line moved {right}."
        assert panel.feedback.text() == expected


def test_escape_during_a_run_turns_the_array_off_and_pauses(window, qtbot):
    panel = window.experiments
    choose(panel, "exp2")
    panel.start()
    press(qtbot, window, QtCore.Qt.Key.Key_G)
    wait_trial(qtbot, panel, "direction")
    trial = panel.runner.current
    qtbot.keyClick(panel.prompt, QtCore.Qt.Key.Key_Escape)
    assert not window.state.scene.playing
    assert "Paused" in panel.prompt.text()
    press(qtbot, window, QtCore.Qt.Key.Key_Up)  # ignored while paused
    assert panel.runner.current is trial
    qtbot.keyClick(panel.prompt, QtCore.Qt.Key.Key_Return)
    assert window.state.scene.playing and window.state.scene.shape == trial.scene.shape


def test_calibration_presents_one_tactor_at_the_staircase_level(window, qtbot):
    panel = window.experiments
    choose(panel, "calibration")
    panel.start()
    trial = panel.runner.current
    col, row = map(int, trial.info["tactor"].split())
    scene = window.state.scene
    assert scene.gain == pytest.approx(float(trial.info["level"])) and scene.method == "CT"

    # Only that tactor, at half drive: floor(0.5 * 22 + 0.5) = 11 (the pulse lasts 0.5 s).
    def only_that_tactor():
        levels = window.device.sent_levels()
        return levels[row, col] == 11 and levels.sum() == 11

    qtbot.waitUntil(only_that_tactor, timeout=5000)
    press(qtbot, window, QtCore.Qt.Key.Key_Y)
    qtbot.waitUntil(
        lambda: panel.runner.current is not trial and not panel.gap_timer.isActive(), timeout=2000
    )
    assert float(panel.runner.current.info["level"]) == pytest.approx(0.35)  # felt: x 0.7
    press(qtbot, window, QtCore.Qt.Key.Key_R)  # feel it again: still the same trial
    assert panel.runner.done == 1


def test_saving_a_calibrated_profile_puts_it_to_use(window, tmp_path):
    window.experiments.last_calibration = ([0.05] * 30, [0.9] * 30, [0.3] * 30)
    path = tmp_path / "calibrated.json"
    assert window.save_calibrated_profile(path)
    assert window.device.profile.calibrated
    assert window.device.profile.offset[0] == pytest.approx(0.05)
    from tactile_core.device.profile import load_profile

    assert load_profile(path).gain[29] == pytest.approx(0.9)
    assert load_profile(path).threshold[3] == pytest.approx(0.3)


def test_bad_participant_id_is_refused(window):
    panel = window.experiments
    panel.participant_edit.setText("../../etc")
    assert not panel.start()
    assert "participant" in window.last_error and not panel.running


def test_analyze_button_shows_the_tables(window, qtbot, tmp_path):
    from tactile_core.cli import main

    assert (
        main(
            ["simulate", str(tmp_path / "results"), "--participants", "4", "--experiments", "exp3"]
        )
        == 0
    )
    panel = window.experiments
    assert panel.run_analysis()  # in the background: the window stays responsive
    qtbot.waitUntil(lambda: "Table 2" in panel.output.toPlainText(), timeout=60_000)
    assert "CT, MM" in panel.output.toPlainText()
    fixed = QtGui.QFontDatabase.systemFont(QtGui.QFontDatabase.SystemFont.FixedFont)
    assert panel.output.font().family() == fixed.family()  # tables line up
    assert panel.figures.count() == 1 and panel.figures.tabText(0) == "fig8-exp3-scores"
    assert not panel.figures.widget(0).widget().pixmap().isNull()


def test_scene_gain_scales_what_is_sent(window, qtbot):
    window.tabs.setCurrentIndex(0)
    # The master intensity scales the part above mu: 0.33 + 0.5 * 0.67 = 0.665 -> 14.63 -> 15;
    # at mu = 0 it is the drive itself: 0.5 -> 11.
    window.state.update(shape=tc.Line((2.5, 3.5), (2.5, 3.5)), method="CT", pause_s=0.0, gain=0.5,
                        dither=False, mu=0.33)  # fmt: skip
    qtbot.waitUntil(lambda: window.device.sent_levels()[3, 2] == 15, timeout=5000)
    window.state.update(mu=0.0)
    qtbot.waitUntil(lambda: window.device.sent_levels()[3, 2] == 11, timeout=5000)


def test_an_experiment_runs_against_a_port(window, qtbot, emulator_thread):
    emulator, path = emulator_thread
    window.device_panel.port_combo.setCurrentText(path)
    qtbot.mouseClick(window.device_panel.connect_button, QtCore.Qt.MouseButton.LeftButton)
    assert not window.device.simulated, window.last_error
    panel = window.experiments
    choose(panel, "exp3")
    panel.start()
    press(qtbot, window, QtCore.Qt.Key.Key_G)
    for _ in range(2):
        wait_trial(qtbot, panel, "shape")
        n = len(emulator.levels)
        qtbot.waitUntil(lambda n=n: len(emulator.levels) > n + 30, timeout=5000)
        assert any(any(levels) for levels in emulator.levels[n:])  # the stimulus is on the wire
        press(qtbot, window, QtCore.Qt.Key.Key_C)
    panel.stop()
    qtbot.waitUntil(lambda: not any(emulator.levels[-1]), timeout=3000)


# --- a participant's window, an experimenter's console ----------------------------------------


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
    panel.participant_edit.setText("")
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
    from tactile_core.device.streamer import StreamStats

    panel = window.experiments
    panel.stats = lambda: StreamStats(state="disconnected", status="device disconnected: /dev/x")
    assert not panel.start() and not panel.running
    assert "not connected" in window.last_error and "/dev/x" in window.last_error


def test_a_lost_link_pauses_the_run_and_the_trial_is_presented_again(window, qtbot, tmp_path):
    from tactile_core.device.streamer import StreamStats

    panel = window.experiments
    choose(panel, "exp3")
    panel.start()
    press(qtbot, window, QtCore.Qt.Key.Key_G)
    wait_trial(qtbot, panel, "shape")
    trial = panel.runner.current
    panel.on_device_status(StreamStats(state="disconnected", status="device disconnected"))
    assert not window.state.scene.playing  # the array is off
    assert "link lost" in panel.log.toPlainText()
    assert not panel.submit(trial.info["shape"])  # no answers while the link is down
    panel.on_device_status(StreamStats(state="streaming", status="reconnected"))
    assert "back" in panel.log.toPlainText() and panel.resume_button.isEnabled()
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
    assert panel._paused and not window.state.scene.playing


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
        panel.rating_edit.setText(text)
        qtbot.keyClick(panel.rating_edit, QtCore.Qt.Key.Key_Return)
        assert "0 to 100" in panel.participant_window.rating_error.text()
        assert panel.runner.done == done
    panel.rating_edit.setText("100")
    qtbot.keyClick(panel.rating_edit, QtCore.Qt.Key.Key_Return)
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
    assert not panel.submit("circle")
    assert panel.runner.current == trial and "No space" in window.last_error
    monkeypatch.undo()
    assert panel.submit("circle")
    assert panel.runner.done == 2


@pytest.fixture
def quick_tuning(monkeypatch):
    import functools

    import tactile_tuner.experiments
    from tactile_core.experiments import RUNNERS
    from tactile_core.experiments.tuning import CorrectionTuning, TuningPlan

    monkeypatch.setattr(tactile_tuner.experiments, "INTERVAL_S", 0.03)
    monkeypatch.setattr(tactile_tuner.experiments, "INTERVAL_GAP_S", 0.02)
    monkeypatch.setitem(
        RUNNERS, "correction", functools.partial(CorrectionTuning, plan=TuningPlan(12, 16, 4))
    )


def test_tune_by_feel_guides_plays_two_intervals_and_applies_the_result(
    window, qtbot, quick_tuning, tmp_path
):
    from tactile_core.experiments.tuning import SimulatedObserver

    panel = window.experiments
    window.start_tuning()
    assert window.tabs.currentWidget() is panel
    assert panel.experiment_combo.currentData() == "correction"
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
    assert panel.intervals_playing
    press(qtbot, window, Key.Key_1)
    assert panel.runner.done == 1  # only the instructions so far
    observer = SimulatedObserver(0.3, 1.0, seed=4)
    while panel.runner is not None:
        qtbot.waitUntil(lambda: not panel.intervals_playing and not panel.gap_timer.isActive(),
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
    dialog = window.tuning_dialog
    assert f"{result.mu:.3f}" in dialog.findChild(QtWidgets.QPlainTextEdit).toPlainText()
    dialog.apply_button.click()
    assert (window.state.scene.mu, window.state.scene.gamma) == (result.mu, result.gamma)
    assert panel.save_profile_button.isEnabled()  # the thresholds feed the calibration


def test_escape_while_the_intervals_play_pauses_with_the_array_off(window, qtbot, quick_tuning):
    panel = window.experiments
    choose(panel, "correction")
    assert panel.start()
    press(qtbot, window, QtCore.Qt.Key.Key_G)
    assert panel.intervals_playing
    qtbot.keyClick(window.experiments.prompt, QtCore.Qt.Key.Key_Escape)
    assert not panel.intervals_playing and not window.state.scene.playing
    qtbot.wait(150)  # the interval timer would have played interval 2 by now
    assert not window.state.scene.playing
    panel.present_again()
    assert panel.intervals_playing
