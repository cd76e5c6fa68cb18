"""What the participant sees and presses during a run: the silent gap and the ready screens
take no key early or twice, feedback goes when the next trial plays, a paused run names no
answer keys, the interval markers are large, the end is shown, and Present again brings back a
closed participant window."""

import time

from PySide6 import QtCore

from . import experiments_gui_support as support
from .experiments_gui_support import choose, press, start_exp2, wait_trial

quick_runs = support.quick_runs  # autouse: no pause between questions
window = support.window
Key = QtCore.Qt.Key


def test_r_in_the_silent_gap_does_not_play_the_next_trial_early(window, qtbot, monkeypatch):
    import tactile_tuner.experiments.trials as trials_module

    monkeypatch.setattr(trials_module, "GAP_S", 0.5)
    panel = window.experiments
    choose(panel, "calibration")
    assert panel.start()
    qtbot.waitUntil(lambda: panel.runner.current is not None, timeout=3000)
    while panel.runner.current.kind != "detect":
        press(qtbot, window, Key.Key_G)
    press(qtbot, window, Key.Key_Y)
    assert panel.trials.gap_timer.isActive()
    before = window.state.scene
    press(qtbot, window, Key.Key_R)
    assert window.state.scene is before  # silence until the gap ends


def test_a_ready_screen_takes_space_and_enter_but_not_a_key_pressed_twice(window, qtbot,
                                                                          monkeypatch):  # fmt: skip
    import tactile_tuner.experiments.trials as trials_module

    panel = window.experiments
    choose(panel, "exp2")
    assert panel.start()
    assert panel.runner.current.kind == "continue"  # the introduction
    monkeypatch.setattr(trials_module, "CONTINUE_GUARD_S", 60.0)
    panel.trials.trial_started = time.monotonic()
    press(qtbot, window, Key.Key_C)  # the last answer's key again: the screen stays
    assert panel.runner.current.kind == "continue"
    monkeypatch.setattr(trials_module, "CONTINUE_GUARD_S", 0.0)
    press(qtbot, window, Key.Key_Space)  # letters only, before
    wait_trial(qtbot, panel, "direction")


def test_present_again_brings_back_a_closed_participant_window(window, qtbot):
    panel = start_exp2(window, qtbot)
    window.all_off()
    panel.participant_window.close()
    panel.trials.present_again()
    assert panel.participant_window.isVisible() and not panel.trials.paused


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
