"""The desk, second pass (issue 19), on the Experiments tab: what the participant and the
experimenter see and press during a run."""

import re

from PySide6 import QtCore

from tactile_core.experiments.results import SESSION_FILE

from . import experiments_gui_support as support
from .experiments_gui_support import choose, press, rows, wait_trial

quick_runs = support.quick_runs  # autouse: no pause between questions
window = support.window
Key = QtCore.Qt.Key


def test_enter_in_the_participant_field_before_start_counts_one_presentation(
    window, qtbot, tmp_path
):
    panel = window.experiments
    choose(panel, "exp2")
    field = panel.setup.participant_edit
    field.setFocus()
    qtbot.keyClick(field, Key.Key_Return)
    qtbot.mouseClick(panel.setup.start_button, QtCore.Qt.MouseButton.LeftButton)
    assert panel.running
    panel.stop()  # a false start: the count of the next run is its own
    field.setFocus()
    qtbot.keyClick(field, Key.Key_Return)
    qtbot.mouseClick(panel.setup.start_button, QtCore.Qt.MouseButton.LeftButton)
    press(qtbot, window, Key.Key_G)  # the introduction, shown once in this run
    wait_trial(qtbot, panel, "direction")
    press(qtbot, window, Key.Key_Up)
    qtbot.waitUntil(lambda: len(rows(panel.runner.path)) >= 2, timeout=3000)
    assert [r["presentations"] for r in rows(panel.runner.path)] == ["1", "1"]


def test_experiment2_feedback_is_gone_when_the_next_trial_plays(window, qtbot):
    panel = window.experiments
    choose(panel, "exp2")
    panel.start()
    press(qtbot, window, Key.Key_G)
    wait_trial(qtbot, panel, "direction")
    first = panel.runner.current
    press(qtbot, window, Key.Key_Up)
    assert panel.participant_window.feedback.text()  # during the silent gap
    qtbot.waitUntil(lambda: panel.runner.current is not first, timeout=3000)
    wait_trial(qtbot, panel, "direction")
    assert panel.participant_window.feedback.text() == ""


def test_a_paused_run_says_nothing_of_space_nor_of_answer_keys(window, qtbot):
    panel = window.experiments
    choose(panel, "exp2")
    panel.start()
    press(qtbot, window, Key.Key_G)
    wait_trial(qtbot, panel, "direction")
    qtbot.keyClick(panel.participant_window.prompt, Key.Key_Escape)
    assert "Space" not in window.statusBar().currentMessage()
    assert "paused" in window.statusBar().currentMessage()
    shown = panel.participant_window.keys_label.text()
    assert "arrow" not in shown and "Paused" in panel.participant_window.prompt.text()


def test_ctrl_q_during_a_run_asks_first(window, qtbot):
    panel = window.experiments
    choose(panel, "exp2")
    panel.start()
    asked = []
    window.confirm = lambda title, text: asked.append(text) or False
    window.activateWindow()
    qtbot.keyClick(window.tabs, Key.Key_Q, QtCore.Qt.KeyboardModifier.ControlModifier)
    assert asked and "experiment is running" in asked[0]
    assert panel.running and window.isVisible()
    window.confirm = lambda title, text: True


def test_the_console_and_the_bar_count_the_same_trials(window, qtbot):
    from tactile_tuner.experiments.guided import tuning_intro

    panel = window.experiments
    window.start_tuning()
    said = int(re.search(r"(\d+) trials", tuning_intro()).group(1))
    assert panel.start()
    assert panel.progress.maximum() == said == panel.runner.total


def test_resume_is_offered_only_for_an_experiment_the_participant_ran(window, qtbot, tmp_path):
    panel = window.experiments
    choose(panel, "exp1")
    assert panel.start()
    panel.stop()
    assert (tmp_path / "results" / "participant-P01" / SESSION_FILE).exists()
    asked = []
    panel.confirm = lambda title, text: asked.append(text) or False
    choose(panel, "exp2")
    panel.start()
    assert "Resume" not in asked[0] and "Start Experiment 2" in asked[0]
    choose(panel, "exp1")
    panel.start()
    assert "Resume Experiment 1" in asked[1]


def test_interval_markers_are_large_and_the_participant_sees_the_end(window, qtbot):
    panel = window.experiments
    pw = panel.participant_window
    assert pw.countdown.font().pointSize() >= pw.prompt.font().pointSize()
    choose(panel, "exp2")
    assert panel.start()
    panel.trials._finish()  # as after the last answer
    assert not panel.running and pw.isVisible()
    assert "finished" in pw.prompt.text().lower() and pw.keys_label.text() == ""
    qtbot.keyClick(pw.prompt, Key.Key_Space)  # the participant's keys play nothing now
    assert not window.state.scene.playing
    panel.start()  # the next run takes the window over again
    assert panel.running and "finished" not in pw.prompt.text().lower()
