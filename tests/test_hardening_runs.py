"""An operator's pass on the Experiments tab: what a technician does wrong during a run. Each
test failed on the code before its fix."""

import json
import shutil
import time
from pathlib import Path

import pytest
from PySide6 import QtCore

from tactile_core.experiments import RUNNERS
from tactile_core.experiments.results import SESSION_FILE, open_session
from tactile_core.files.presets import builtin_presets

from . import experiments_gui_support as support
from .experiments_gui_support import choose, press, rows, wait_trial

quick_runs = support.quick_runs  # autouse: no pause between questions
window = support.window
Key = QtCore.Qt.Key


def start_exp2(window, qtbot):
    panel = window.experiments
    choose(panel, "exp2")
    assert panel.start()
    press(qtbot, window, Key.Key_G)  # the introduction
    wait_trial(qtbot, panel, "direction")
    return panel


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


def test_present_again_brings_back_a_closed_participant_window(window, qtbot):
    panel = start_exp2(window, qtbot)
    window.all_off()
    panel.participant_window.close()
    panel.trials.present_again()
    assert panel.participant_window.isVisible() and not panel.trials.paused


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


# --- the session on disk -----------------------------------------------------------------------


def test_a_copy_refused_the_participant_writes_nothing_to_their_session(tmp_path):
    # Exp. 3's emphasis and method set were saved before the lock was taken: a second copy,
    # refused, had already rewritten session.json, and Exp. 3 was then refused with the
    # participant's real emphasis ("differs from the session's 0.5").
    first = RUNNERS["exp2"](open_session(tmp_path, "P01"))
    try:
        path = tmp_path / "participant-P01" / SESSION_FILE
        before = path.read_bytes()
        with pytest.raises(Exception, match="being recorded by"):
            RUNNERS["exp3"](open_session(tmp_path, "P01"), emphasis=0.5, methods=["CT", "MM"])
        assert path.read_bytes() == before
        assert "exp3_emphasis" not in json.loads(before).get("parameters", {})
    finally:
        first.close()
    third = RUNNERS["exp3"](open_session(tmp_path, "P01"), emphasis=0.0)
    third.close()  # the participant's own emphasis, accepted


def test_a_deleted_participant_does_not_give_the_next_one_anothers_orders(tmp_path):
    for pid in ("P01", "P0l", "P02"):  # a typo among them, deleted afterwards
        open_session(tmp_path, pid)
    shutil.rmtree(tmp_path / "participant-P0l")
    assert open_session(tmp_path, "P03").index == 3  # was 2, P02's: the same orders
    assert open_session(tmp_path, "P02").index == 2


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


def test_a_run_stopped_before_its_first_answer_may_start_again_otherwise(tmp_path):
    # A mistyped method set or emphasis, started and stopped at once, could only be undone
    # with a new participant id (and so another recruitment index).
    wrong = RUNNERS["exp3"](open_session(tmp_path, "P01"), emphasis=0.5, methods=["CT", "MM"])
    wrong.close()  # no answer
    paper = ["CT", "MM", "AS", "IM"]
    right = RUNNERS["exp3"](open_session(tmp_path, "P01"), emphasis=0.0, methods=paper)
    assert right.methods == ["CT", "MM", "AS", "IM"] and right.emphasis == 0.0
    right.answer("continue", rt_s=0.5)  # the first screen: now an answer is recorded
    right.close()
    session = json.loads((tmp_path / "participant-P01" / SESSION_FILE).read_text())
    assert session["parameters"]["exp3_emphasis"] == 0.0
    assert session["parameters"]["exp3_methods"] == ["CT", "MM", "AS", "IM"]
    with pytest.raises(ValueError, match=r"emphasis 0\.5 differs from the session.s 0"):
        RUNNERS["exp3"](open_session(tmp_path, "P01"), emphasis=0.5)
