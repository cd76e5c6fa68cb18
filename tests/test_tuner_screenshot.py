"""``tactile-tuner --screenshot`` shows the last session and leaves it as it was."""

import subprocess
import sys

import pytest


def test_a_window_that_does_not_remember_leaves_the_saved_session(qtbot, qt_settings):
    # --screenshot closed a window that saved its own (default) scene over the session's
    from tactile_tuner.window import MainWindow

    first = MainWindow(restore=False, process=False)
    qtbot.addWidget(first)
    first.state.update(method="IM", mu=0.66)
    first.close()  # saves IM, 0.66
    shot = MainWindow(restore=True, process=False, remember=False)
    qtbot.addWidget(shot)
    assert (shot.state.scene.method, shot.state.scene.mu) == ("IM", pytest.approx(0.66))
    shot.state.update(mu=0.1)
    shot.close()  # saves nothing
    again = MainWindow(restore=True, process=False)
    qtbot.addWidget(again)
    assert (again.state.scene.method, again.state.scene.mu) == ("IM", pytest.approx(0.66))
    again.close()


def test_the_screenshot_command_neither_resets_nor_saves_the_session(tmp_path):
    env = {"QT_QPA_PLATFORM": "offscreen", "HOME": str(tmp_path), "PATH": "/usr/bin:/bin",
           "XDG_CONFIG_HOME": str(tmp_path / "config")}  # fmt: skip
    config = tmp_path / "config" / "tactile-tuner" / "tactile-tuner.conf"

    def shoot():
        out = subprocess.run(
            [sys.executable, "-m", "tactile_tuner.main", "--screenshot", str(tmp_path / "s.png")],
            capture_output=True, text=True, timeout=120, env=env,
        )  # fmt: skip
        assert out.returncode == 0, out.stderr

    shoot()
    assert not config.exists()  # a screenshot writes no session of its own
