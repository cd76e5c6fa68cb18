"""One run's trials: each presented on the array and in the participant's window, answered by
key or rating, timed, paused and presented again."""

from __future__ import annotations

import time

from PySide6 import QtCore

from tactile_core.experiments.runners import INTERVAL_GAP_S, INTERVAL_S
from tactile_core.rendering.scene import Scene

KEYS = {
    "continue": "any letter key to go on",
    "prepare": "1-{n} to switch methods, a letter key to go on",
    "rating": "type 0-100, then Enter",
    "direction": "arrow keys",
    "shape": "C for circle, S for square",
    "detect": "Y (felt) or N (not felt); R to feel it again",
    "interval": "1 or 2 once both intervals have played; R to feel both again",
}
GAP_S = 0.8  # the array is off between a question's answer and the next stimulus
CONTINUE_GUARD_S = 0.4
"""A "press a key when ready" screen takes no key this soon after it appears (an answer key
pressed twice would skip it, and the rest it offers)."""
LINK_DOWN = ("disconnected", "stopped", "failed", "refused")
"""Stream states in which the array is not being driven."""


class TrialPresenter(QtCore.QObject):
    """Presents the trials of a run (a runner of :mod:`tactile_core.experiments`).

    Each trial's scene plays through the state (so the array gets it); its prompt, keys and
    rating box go to the participant's window. An answer moves on to the next trial (after a
    silent gap for the forced choices); a time limit answers for the participant. A pause (Esc,
    a lost link, the participant's window closed) turns the array off, and the trial is
    presented again from its beginning; its row records how often it was presented.

    Parameters
    ----------
    state : TunerState
    participant_window : ParticipantWindow
    health : callable, optional
        The stream's counters now (``late_frames``, ``skipped_frames``, ``link_errors``), or
        None; the difference over a trial goes into its row.
    """

    trial_presented = QtCore.Signal(object)
    """The trial now presented (a :class:`~tactile_core.experiments.runners.Trial`)."""
    event_logged = QtCore.Signal(str)
    error_raised = QtCore.Signal(str)
    resumable_changed = QtCore.Signal(bool)
    """Whether *Present again* can resume the run now."""
    finished = QtCore.Signal()
    """Every trial is answered (:attr:`runner` is still set)."""

    def __init__(self, state, participant_window, health=None, parent=None):
        super().__init__(parent)
        self.state = state
        self.participant_window = participant_window
        self.health = health or (lambda: None)
        self.runner = None
        self.paused = False
        self.link_lost = False
        self.trial_started = 0.0
        self._health0 = None
        self._presentations = 0
        self._presented = None  # the trial the count is of
        self._steps: list = []
        pw = participant_window
        self.prompt, self.keys_label, self.feedback = pw.prompt, pw.keys_label, pw.feedback
        self.rating_edit, self.countdown = pw.rating_edit, pw.countdown
        self.rating_edit.returnPressed.connect(self._on_rating_edit_return_pressed)
        pw.closed.connect(self._on_participant_window_closed)
        self.limit_timer = QtCore.QTimer(self)
        self.limit_timer.setSingleShot(True)
        self.limit_timer.timeout.connect(lambda: self.submit(None))
        self.tick_timer = QtCore.QTimer(self)
        self.tick_timer.timeout.connect(self._on_tick_timer_timeout)
        self.gap_timer = QtCore.QTimer(self)
        self.gap_timer.setSingleShot(True)
        self.gap_timer.timeout.connect(self.present)
        # Two-interval trials: interval 1, a gap, interval 2, then the question.
        self.interval_timer = QtCore.QTimer(self)
        self.interval_timer.setSingleShot(True)
        self.interval_timer.timeout.connect(self._next_interval)

    # --- the run -------------------------------------------------------------------------------

    def begin(self, runner) -> None:
        """Take on ``runner`` (a run that starts or resumes); :meth:`present` shows its trial."""
        self.runner = runner
        self.link_lost = False
        self._presentations, self._presented = 0, None  # counted per run and per trial
        self.feedback.setText("")
        self.participant_window.rating_error.setText("")

    def stop(self):
        """Stop presenting (the array is left as it is); the runner, which stays open."""
        self._stop_timers()
        runner, self.runner = self.runner, None
        self.prompt.setText("Please wait.")
        self.rating_edit.setVisible(False)
        return runner

    def release(self):
        """After :attr:`finished`: the runner, no longer presented."""
        runner, self.runner = self.runner, None
        return runner

    def _stop_timers(self) -> None:
        for timer in (self.limit_timer, self.tick_timer, self.gap_timer, self.interval_timer):
            timer.stop()
        self._steps = []
        self.countdown.setText("")

    def _play(self, scene: Scene | None, marker: str = "trial") -> None:
        """Present ``scene`` from its beginning (None: silence); ``marker`` is its kind for the
        LSL markers: ``trial``, or ``interval`` for an interval of guided tuning."""
        current = self.state.scene
        if scene is None:
            self.state.set_scene(current.replace(playing=False), owner=self)
        else:
            self.state.set_scene(scene.replace(epoch=current.epoch + 1, marker=marker), owner=self)

    def present(self) -> None:
        """Present the current trial from its beginning (finish when none is left)."""
        runner = self.runner
        if runner is None:
            return
        trial = runner.current
        if trial is None:
            self._finish()
            return
        self.paused = False
        self.resumable_changed.emit(False)
        self.trial_presented.emit(trial)
        self.feedback.setText("")  # the last answer's feedback belongs to the gap before
        self.prompt.setText(trial.prompt)
        self.keys_label.setText(f"keys: {KEYS[trial.kind].format(n=len(trial.options))}")
        self.rating_edit.setVisible(trial.kind == "rating")
        self.participant_window.rating_error.setText("")
        if trial.kind == "rating":
            self.rating_edit.clear()
            self.rating_edit.setFocus()
        if trial.kind == "interval":
            self.prompt.setText("Feel both intervals.")
            self._play_intervals(trial)
        else:
            self._play(trial.scene)
        if self._presented is not trial:
            self._presented, self._presentations = trial, 0
        self._presentations += 1
        if self._presentations > 1:
            self.event_logged.emit(f"trial {trial.stage} {trial.index} presented again "
                                   f"({self._presentations} times)")  # fmt: skip
        self.trial_started = time.monotonic()
        self._health0 = self.health()
        if trial.time_limit_s:
            self.limit_timer.start(round(trial.time_limit_s * 1000))
            self.tick_timer.start(250)
            self._on_tick_timer_timeout()

    def _finish(self) -> None:
        self._stop_timers()
        self.prompt.setText("Thank you. This part is finished.")
        self.keys_label.setText("")
        self.feedback.setText("")
        self.rating_edit.setVisible(False)
        self.finished.emit()

    def _on_tick_timer_timeout(self) -> None:
        trial = self.runner.current if self.runner else None
        if trial is None or not trial.time_limit_s:
            self.countdown.setText("")
            return
        left = trial.time_limit_s - (time.monotonic() - self.trial_started)
        self.countdown.setText(f"{max(left, 0):.0f} s left")

    # --- two-interval trials ------------------------------------------------------------------

    @property
    def intervals_playing(self) -> bool:
        """True while the intervals of a two-interval trial are being played."""
        return bool(self._steps) or self.interval_timer.isActive()

    def _play_intervals(self, trial) -> None:
        """Play interval 1, a silent gap, interval 2; then ask (the participant's window shows
        which interval is playing, in large type)."""
        one, two = trial.intervals
        self._steps = [(one, INTERVAL_S, "1"), (None, INTERVAL_GAP_S, ""), (two, INTERVAL_S, "2"),
                       (None, 0.0, None)]  # fmt: skip
        self._next_interval()

    def _next_interval(self) -> None:
        if not self._steps:
            return
        scene, seconds, label = self._steps.pop(0)
        self._play(scene, "interval")
        if label is None:  # both played: the question
            self.countdown.setText("")
            self.prompt.setText(self.runner.current.prompt if self.runner and
                                self.runner.current else "")  # fmt: skip
            self.trial_started = time.monotonic()
            return
        self.countdown.setText(f"interval {label}" if label else "")
        self.interval_timer.start(round(seconds * 1000))

    # --- answers -------------------------------------------------------------------------------

    def submit(self, answer) -> bool:
        """Answer the current trial (the UI's keys call this); False if not accepted."""
        runner = self.runner
        if runner is None or runner.current is None or self.gap_timer.isActive() or self.paused:
            return False
        if self.intervals_playing:
            return False  # both intervals first
        trial = runner.current
        rt = time.monotonic() - self.trial_started
        health = {"presentations": self._presentations}
        now, before = self.health(), self._health0
        if now is not None and before is not None:
            # a stream that restarted (its counters too) since the trial began counts from 0
            health.update({key: now[key] - before[key] if now[key] >= before[key] else now[key]
                           for key in now})  # fmt: skip
        try:
            feedback = runner.answer(answer, rt_s=rt, health=health)
        except OSError as exc:  # the disk: the runner stays on this trial; a retry records it
            self.feedback.setText("Please wait.")
            self.event_logged.emit(f"could not record the answer ({exc}); the trial stays: retry")
            self.error_raised.emit(f"could not record the answer: {exc}")
            return False
        except ValueError as exc:
            self.participant_window.rating_error.setText(str(exc))
            return False
        self._presentations = 0
        self._stop_timers()
        self.feedback.setText(feedback)
        if trial.kind in ("direction", "shape", "detect", "interval"):
            self._play(None)  # silence before the next stimulus
            self.gap_timer.start(round(GAP_S * 1000))
        else:
            self.present()
        return True

    def select_key(self, key: int) -> bool:
        """Experiment 1 preparation stage: play the method behind key 1-N."""
        runner = self.runner
        if runner is None or runner.current is None or runner.current.kind != "prepare":
            return False
        self._play(runner.select(key))
        return True

    def replay(self) -> None:
        """Play the current trial's stimulus again (calibration: R), or both its intervals."""
        trial = self.runner.current if self.runner else None
        if trial is None or self.paused or self.gap_timer.isActive():
            return  # (in the gap the next trial would play early, and again when presented)
        if trial.kind == "interval":
            self.interval_timer.stop()
            self._play_intervals(trial)
        elif trial.scene is not None:
            self._play(trial.scene)

    def _on_rating_edit_return_pressed(self) -> None:
        text = self.rating_edit.text().strip()
        try:
            value = int(text)
        except ValueError:
            value = None
        if value is None or not 0 <= value <= 100:
            self.participant_window.rating_error.setText(
                f"A rating is a whole number from 0 to 100; {text or 'nothing'} is not one."
            )
            self.rating_edit.selectAll()
            return
        self.submit(value)

    def handle_key(self, event) -> bool:
        """Keys while running; True if the key was used."""
        runner = self.runner
        if runner is None or runner.current is None:
            return False
        key = event.key()
        k = QtCore.Qt.Key
        if self.paused:
            if key in (k.Key_Return, k.Key_Enter):
                self.present_again()
                return True
            return False
        kind = runner.current.kind
        if kind == "rating":
            return False  # the rating box takes digits and Enter itself
        if kind == "prepare" and k.Key_1 <= key < k.Key_1 + len(runner.current.options):
            return self.select_key(key - k.Key_1 + 1)
        if kind in ("continue", "prepare") and (
            k.Key_A <= key <= k.Key_Z or key in (k.Key_Space, k.Key_Return, k.Key_Enter)
        ):
            if time.monotonic() - self.trial_started < CONTINUE_GUARD_S:
                return True  # the last answer's key pressed twice: not "ready" yet
            return self.submit("continue")
        if kind == "direction":
            arrows = {k.Key_Up: "up", k.Key_Down: "down", k.Key_Left: "left", k.Key_Right: "right"}
            if key in arrows:
                return self.submit(arrows[key])
        if kind == "shape" and key in (k.Key_C, k.Key_S):
            return self.submit("circle" if key == k.Key_C else "square")
        if kind == "interval":
            if key in (k.Key_1, k.Key_2):
                return self.submit("1" if key == k.Key_1 else "2")
            if key == k.Key_R:
                self.replay()
                return True
        if kind == "detect":
            if key in (k.Key_Y, k.Key_N):
                return self.submit("yes" if key == k.Key_Y else "no")
            if key == k.Key_R:
                self.replay()
                return True
        return False

    # --- pauses --------------------------------------------------------------------------------

    def pause(self, why: str = "paused (Esc)") -> None:
        """The array off; the trial is presented again when the run resumes."""
        if self.runner is None:
            return
        self.paused = True
        self._stop_timers()
        self._play(None)
        self.gap_timer.stop()
        self.prompt.setText("Paused. Please wait.")
        self.keys_label.setText("")  # no answer is taken while paused
        self.feedback.setText("")
        self.rating_edit.setVisible(False)
        self.resumable_changed.emit(not self.link_lost)
        trial = self.runner.current
        where = f" at trial {trial.stage} {trial.index}" if trial else ""
        self.event_logged.emit(f"{why}{where}; the array is off")

    def present_again(self) -> None:
        """Resume after a pause: the current trial, from its beginning."""
        if self.runner is None or not self.paused:
            return
        if self.link_lost:
            self.error_raised.emit("the array is still disconnected")
            return
        if not self.participant_window.isVisible():  # closed during the pause: its prompts
            self.participant_window.show()  # and feedback go with the trial
            self.event_logged.emit("the participant's window was closed: shown again")
        self.present()

    def on_device_status(self, stats) -> None:
        """The stream's state changed: a lost link pauses the run; its return is logged."""
        if self.runner is None:
            return
        if stats.state in LINK_DOWN and not self.link_lost:
            self.link_lost = True
            self.pause(f"link lost ({stats.status})")
        elif stats.state in ("streaming", "paused", "idle") and self.link_lost:
            self.link_lost = False
            self.resumable_changed.emit(True)
            self.event_logged.emit("the array is back: press Present again (or Enter)")

    def _on_participant_window_closed(self) -> None:
        if self.runner is not None and not self.paused:
            self.pause("the participant's window was closed")
