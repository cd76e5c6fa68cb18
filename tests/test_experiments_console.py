"""The Experiments tab's console during a run: only the trials change the stimulus (not a
preset, the controls, tuning by feel or another device), the run's fields stay as they are,
All off pauses it, a restarted stream does not refuse an answer, Ctrl+Q asks first, a resumed
session keeps its seed, and the console counts what the participant does."""

import re
from pathlib import Path

from PySide6 import QtCore

from tactile_core.experiments.results import SESSION_FILE
from tactile_core.files.presets import builtin_presets

from . import experiments_gui_support as support
from .experiments_gui_support import choose, press, rows, start_exp2, wait_trial

quick_runs = support.quick_runs  # autouse: no pause between questions
window = support.window
Key = QtCore.Qt.Key


def test_nothing_but_the_trials_changes_the_stimulus_during_a_run(window, qtbot):
    # A built-in preset opened from the File menu played a circle at mu 0.33 while the row
    # recorded the trial's line at mu 0; the controls (View > Controls panel) did the same.
    panel = start_exp2(window, qtbot)
    trial = panel.runner.current
    playing = window.state.scene
    assert not window.files.load_preset_file(builtin_presets()["exp1-circle"])
    assert "An experiment run is going on" in window.last_error
    assert not window.state.update(mu=0.9, gamma=3.0, method="CT")
    window.state.restart()  # Array > Restart trace
    assert window.state.scene == playing
    assert "Stop the run first" in window.statusBar().currentMessage()
    assert playing.mu == trial.scene.mu and playing.shape == trial.scene.shape
    press(qtbot, window, Key.Key_Up)  # what the row records is what played
    qtbot.waitUntil(lambda: len(rows(panel.runner.path)) >= 1, timeout=3000)
    panel.stop()
    assert window.state.update(mu=0.5)  # the tuner's again once the run stopped


def test_all_off_from_the_menu_pauses_the_run_as_it_says(window, qtbot):
    panel = start_exp2(window, qtbot)
    window.all_off()  # Array > All off
    assert panel.trials.paused and panel.setup.resume_button.isEnabled()
    assert not panel.trials.submit("up")  # no answer while the array is off
    assert "the run is paused" in window.statusBar().currentMessage()


def test_the_device_and_the_session_fields_stay_as_they_are_during_a_run(window, qtbot):
    # Another port, a disconnect (the simulated array took over silently) or a new lead (the
    # stream restarted, its counters with it: every answer then failed "late_frames must be
    # >= 0") changed what the trials record; the participant id and folder stayed editable.
    panel = start_exp2(window, qtbot)
    dock = window.device_panel
    for widget in (dock.port_combo, dock.connect_button, dock.disconnect_button,
                   dock.lead_spin, panel.setup.participant_edit, panel.setup.folder_edit,
                   panel.setup.start_button):  # fmt: skip
        assert not widget.isEnabled()
    panel.stop()
    assert dock.lead_spin.isEnabled() and panel.setup.participant_edit.isEnabled()


def test_a_stream_restarted_mid_trial_does_not_refuse_the_answer(window, qtbot):
    panel = start_exp2(window, qtbot)
    panel.trials._health0 = {"late_frames": 40, "skipped_frames": 3, "link_errors": 0}
    panel.trials.health = lambda: {"late_frames": 2, "skipped_frames": 0, "link_errors": 0}
    assert panel.trials.submit("up")  # it failed "late_frames must be >= 0, got -38"
    row = rows(panel.runner.path)[-1]
    assert row["late_frames"] == "2" and row["skipped_frames"] == "0"


def test_the_results_folder_is_the_users_not_taken_literally(window, qtbot, tmp_path,
                                                            monkeypatch):  # fmt: skip
    panel = window.experiments
    choose(panel, "exp2")
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    monkeypatch.chdir(tmp_path)
    panel.setup.folder_edit.setText("  ")
    assert not panel.start()
    assert "the results folder is empty" in window.last_error
    panel.setup.folder_edit.setText("~/res")
    assert panel.start()
    assert Path(panel.runner.path).is_relative_to(tmp_path / "home" / "res")
    assert not (tmp_path / "~").exists()


def test_tuning_by_feel_is_refused_during_a_run(window, qtbot):
    panel = start_exp2(window, qtbot)
    window.start_tuning()  # Array > Tune the correction by feel...
    assert panel.setup.experiment == "exp2" and panel.running
    assert "Stop it first" in window.statusBar().currentMessage()


def test_a_resumed_session_keeps_its_seed_and_says_so(window, qtbot):
    panel = window.experiments
    choose(panel, "exp2")
    panel.setup.seed_spin.setValue(7)
    assert panel.start()
    panel.stop()
    panel.setup.seed_spin.setValue(8)  # the seed typed differs: it was ignored without a word
    assert panel.start()
    assert panel.setup.seed_spin.value() == 7 and panel.runner.session.seed == 7
    assert "has seed 7, not 8: it keeps its own" in panel.log.toPlainText()


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
