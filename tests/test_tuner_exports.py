"""The tuner's exports of what it shows: the activation curves as CSV, on the frames' clock."""

import numpy as np
import pytest

pytestmark = pytest.mark.usefixtures("qt_settings")


@pytest.fixture
def window(qtbot):
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False, process=False)
    qtbot.addWidget(win)
    win.show()
    qtbot.waitExposed(win)
    yield win
    win.close()


@pytest.mark.parametrize(("duration_s", "rate_hz"), [(1.0, 400.0), (2.0, 300.0), (0.5, 1000.0)])
def test_the_curves_csv_steps_one_frame_period_over_the_trace(window, tmp_path, duration_s,
                                                              rate_hz):  # fmt: skip
    # The time column stepped 2/399 s (400 samples over a 2 s trace), not a frame period.
    window.state.update(duration_s=duration_s, rate_hz=rate_hz)
    window.tune.refresh()
    path = tmp_path / "curves.csv"
    assert window.files.export_curves(path)
    time_s = np.loadtxt(path, delimiter=",", skiprows=1, usecols=0)
    n = round(duration_s * rate_hz)  # frame periods in the trace: n + 1 samples, 0 to the end
    # (the CSV writes 8 significant digits)
    np.testing.assert_allclose(time_s, np.arange(n + 1) / rate_hz, rtol=1e-7, atol=1e-12)
    assert time_s[-1] == duration_s
