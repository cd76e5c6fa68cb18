"""Fixtures and helpers of the Experiments tab's GUI tests (test_tuner_experiments.py and
test_tuner_console.py): a window whose console is set up and answers yes, short gaps, keys."""

import csv

import pytest


@pytest.fixture(autouse=True)
def quick_runs(qt_settings, monkeypatch):
    import tactile_tuner.experiments.trials

    monkeypatch.setattr(
        tactile_tuner.experiments.trials, "GAP_S", 0.01
    )  # no pause between questions in tests
    monkeypatch.setattr(tactile_tuner.experiments.trials, "CONTINUE_GUARD_S", 0.0)


@pytest.fixture
def window(qtbot, tmp_path):
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False, process=False)  # the stream as a thread: quicker
    qtbot.addWidget(win)
    win.show()
    qtbot.waitExposed(win)
    panel = win.experiments
    panel.setup.folder_edit.setText(str(tmp_path / "results"))
    panel.setup.participant_edit.setText("P01")
    panel.confirm = lambda title, text: True  # the experimenter says yes
    win.confirm = lambda title, text: True  # also to quitting during a run
    win.tabs.setCurrentWidget(panel)
    yield win
    panel.stop()
    win.close()


def choose(panel, name):
    panel.setup.experiment_combo.setCurrentIndex(panel.setup.experiment_combo.findData(name))


def press(qtbot, win, key, text=""):
    qtbot.keyClick(win.experiments.participant_window.prompt, key)


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def wait_trial(qtbot, panel, kind):
    qtbot.waitUntil(
        lambda: panel.runner is not None and panel.runner.current is not None
        and panel.runner.current.kind == kind and not panel.trials.gap_timer.isActive(),
        timeout=3000,
    )  # fmt: skip


def start_exp2(window, qtbot):
    """Start Experiment 2 in the console, past its introduction, at its first trial."""
    from PySide6 import QtCore

    panel = window.experiments
    choose(panel, "exp2")
    assert panel.start()
    press(qtbot, window, QtCore.Qt.Key.Key_G)  # the introduction
    wait_trial(qtbot, panel, "direction")
    return panel


@pytest.fixture
def quick_tuning(monkeypatch):
    import functools

    import tactile_tuner.experiments.trials
    from tactile_core.experiments import RUNNERS
    from tactile_core.experiments.tuning import CorrectionTuning, TuningPlan

    monkeypatch.setattr(tactile_tuner.experiments.trials, "INTERVAL_S", 0.01)
    monkeypatch.setattr(tactile_tuner.experiments.trials, "INTERVAL_GAP_S", 0.005)
    monkeypatch.setitem(
        RUNNERS, "correction", functools.partial(CorrectionTuning, plan=TuningPlan(12, 16, 4))
    )
