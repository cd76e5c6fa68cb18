"""The tuner's Experiments tab, driven from the keyboard against the simulated array: the
paper's experiments, the calibration, and the analysis of a results folder."""

import json

import pytest
from PySide6 import QtCore, QtGui

import tactile_core as tc

from . import experiments_gui_support as support
from .experiments_gui_support import choose, press, rows, wait_trial
from .helpers import record_sent

quick_runs = support.quick_runs  # autouse: no pause between questions
window = support.window


def test_experiment3_by_keyboard_hides_the_display_and_records_every_answer(
    window, qtbot, tmp_path
):
    panel = window.experiments
    choose(panel, "exp3")
    assert panel.start()
    assert window.tune.currentIndex() == 1 and not window.tabs.isTabEnabled(0)
    assert not window.controls_dock.isVisible()  # its shape fields would give the answer away
    assert not window.device_panel.status_label.isVisible()  # so would "streaming MM at ..."
    assert "Experiment 3" in panel.participant_window.prompt.text()
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
                lambda: panel.runner is None or not panel.trials.gap_timer.isActive(), timeout=2000
            )
    assert answered == 40
    assert (
        "Finished" in panel.run_label.text()
        and "finished" in panel.participant_window.prompt.text()
    )
    assert window.tune.currentIndex() == 0 and window.tabs.isTabEnabled(0)
    assert window.controls_dock.isVisible()
    data = rows(tmp_path / "results" / "participant-P01" / "exp3.csv")
    questions = [r for r in data if r["stage"] in ("CT", "MM", "AS", "IM")]
    assert len(questions) == 40 and all(r["correct"] == "1" for r in questions)
    assert all(float(r["rt_s"]) >= 0 for r in questions)
    assert not window.state.scene.playing  # the array is off at the end


def test_experiment3_time_limit_records_a_timeout(window, qtbot, monkeypatch, tmp_path):
    import tactile_tuner.experiments.trials
    from tactile_core.experiments import runners

    # long enough for the countdown to be seen before the limit ends the trial on a loaded host
    monkeypatch.setattr(runners.Experiment3, "TIME_LIMIT_S", 1.5)
    # the feedback shows through the silent gap; a gap of 10 ms (quick_runs) could end, and
    # the next trial clear it, before a loaded machine polls it
    monkeypatch.setattr(tactile_tuner.experiments.trials, "GAP_S", 60.0)
    panel = window.experiments
    choose(panel, "exp3")
    panel.start()
    press(qtbot, window, QtCore.Qt.Key.Key_G)
    wait_trial(qtbot, panel, "shape")
    assert "s left" in panel.participant_window.countdown.text()
    qtbot.waitUntil(lambda: panel.runner.done == 2, timeout=10_000)  # nobody answered
    assert panel.trials.gap_timer.isActive()
    assert panel.participant_window.feedback.text().startswith("Time is up: it was a")
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
    assert (
        panel.runner.current.kind == "rating" and panel.participant_window.rating_edit.isVisible()
    )
    for value in ("85", "40"):
        qtbot.keyClicks(panel.participant_window.rating_edit, value)
        qtbot.keyClick(panel.participant_window.rating_edit, Key.Key_Return)
    qtbot.keyClicks(panel.participant_window.rating_edit, "100")
    qtbot.keyClick(panel.participant_window.rating_edit, Key.Key_Return)
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
    panel.setup.methods_edit.edit.setText("AS EN RO:r=1.5")
    panel.setup.methods_edit.edit.editingFinished.emit()
    assert panel.setup.methods_edit.methods == ["AS", "EN", "RO:r=1.5"]
    assert panel.start()
    Key = QtCore.Qt.Key
    mapping = panel.runner.mapping
    assert sorted(mapping) == ["AS", "EN", "RO:r=1.5"]
    assert "1-3" in panel.participant_window.keys_label.text()
    press(qtbot, window, Key.Key_3)
    assert window.state.scene.method == mapping[2]
    press(qtbot, window, Key.Key_4)  # no fourth method: nothing changes
    assert window.state.scene.method == mapping[2] and panel.runner.current.kind == "prepare"
    session = json.loads((tmp_path / "results" / "participant-P01" / "session.json").read_text())
    assert session["parameters"]["exp1_methods"] == ["AS", "EN", "RO:r=1.5"]
    # Stopped and resumed with the console back at the paper's four: the participant's own set
    # comes back (a console at its default never overrides what a session recorded).
    panel.stop()
    panel.setup.methods_edit.apply(["CT", "MM", "AS", "IM"])
    assert panel.start()
    assert panel.runner.methods == ["AS", "EN", "RO:r=1.5"]
    assert panel.setup.methods_edit.methods == ["AS", "EN", "RO:r=1.5"]
    panel.stop()
    # A bad set typed into the console is refused on the spot; the last good set stays.
    panel.setup.methods_edit.edit.setText("AS")
    panel.setup.methods_edit.edit.editingFinished.emit()
    assert "choose 2 to 8" in panel.setup.methods_edit.problem.text()
    assert panel.setup.methods_edit.methods == ["AS", "EN", "RO:r=1.5"]


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
        assert panel.participant_window.feedback.text() == expected


def test_escape_during_a_run_turns_the_array_off_and_pauses(window, qtbot):
    panel = window.experiments
    choose(panel, "exp2")
    panel.start()
    press(qtbot, window, QtCore.Qt.Key.Key_G)
    wait_trial(qtbot, panel, "direction")
    trial = panel.runner.current
    qtbot.keyClick(panel.participant_window.prompt, QtCore.Qt.Key.Key_Escape)
    assert not window.state.scene.playing
    assert "Paused" in panel.participant_window.prompt.text()
    press(qtbot, window, QtCore.Qt.Key.Key_Up)  # ignored while paused
    assert panel.runner.current is trial
    qtbot.keyClick(panel.participant_window.prompt, QtCore.Qt.Key.Key_Return)
    assert window.state.scene.playing and window.state.scene.shape == trial.scene.shape


def test_calibration_presents_one_tactor_at_the_staircase_level(window, qtbot):
    panel = window.experiments
    choose(panel, "calibration")
    sent = record_sent(window)
    panel.start()
    trial = panel.runner.current
    col, row = map(int, trial.info["tactor"].split())
    scene = window.state.scene
    assert scene.gain == pytest.approx(float(trial.info["level"])) and scene.method == "CT"

    # Only that tactor, at half drive: floor(0.5 * 22 + 0.5) = 11. The pulse lasts 0.5 s:
    # every frame is looked at, not the newest one (it may be over when the test looks).
    def only_that_tactor():
        return any(lv[row * 5 + col] == 11 and lv.sum() == 11 for lv in list(sent))

    qtbot.waitUntil(only_that_tactor, timeout=5000)
    press(qtbot, window, QtCore.Qt.Key.Key_Y)
    qtbot.waitUntil(
        lambda: panel.runner.current is not trial and not panel.trials.gap_timer.isActive(),
        timeout=2000,
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
    panel.setup.participant_edit.setText("../../etc")
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
    assert panel.analysis.run_analysis()  # in the background: the window stays responsive
    qtbot.waitUntil(lambda: "Table 2" in panel.analysis.output.toPlainText(), timeout=60_000)
    assert "CT, MM" in panel.analysis.output.toPlainText()
    fixed = QtGui.QFontDatabase.systemFont(QtGui.QFontDatabase.SystemFont.FixedFont)
    assert panel.analysis.output.font().family() == fixed.family()  # tables line up
    assert (
        panel.analysis.figures.count() == 1
        and panel.analysis.figures.tabText(0) == "fig8-exp3-scores"
    )
    assert not panel.analysis.figures.widget(0).widget().pixmap().isNull()


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
        n = len(emulator.log)
        qtbot.waitUntil(lambda n=n: len(emulator.log) > n + 30, timeout=5000)
        assert emulator.log.arrays(n)[2].any()  # the stimulus is on the wire
        press(qtbot, window, QtCore.Qt.Key.Key_C)
    panel.stop()
    qtbot.waitUntil(lambda: not any(emulator.log.last()), timeout=3000)
