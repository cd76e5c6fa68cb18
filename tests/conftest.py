"""Shared test set-up: offscreen Qt, deterministic hypothesis, numpy errors as exceptions."""

import os
import threading

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
# One BLAS thread in this process and every process it starts, before numpy is imported: the
# suite's fits are small, and OpenBLAS's extra threads busy-wait (with a CPU hog beside the
# suite they made the analysis tests 19 times slower; tactile_core/_shared/threads.py).
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import pytest
from hypothesis import HealthCheck, settings

from .emulator_support import Emulator

settings.register_profile(
    "default",
    deadline=None,
    derandomize=True,  # the same examples in every run
    database=None,  # and no examples replayed from earlier runs: a run depends on the code only
    max_examples=150,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile("thorough", deadline=None, max_examples=2000)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "default"))


def _emulator_in_a_thread(socket: bool):
    from tactile_core.device.emulator import Emulator

    emulator = Emulator()
    path = emulator.open_socket() if socket else emulator.open()
    stop = threading.Event()
    thread = threading.Thread(target=emulator.run, args=(stop.is_set,), daemon=True)
    thread.start()
    yield emulator, path
    stop.set()
    thread.join(2)
    emulator.close()


@pytest.fixture
def emulator_thread():
    """A device emulator on a pseudo-terminal, receiving in a thread: ``(emulator, path)``."""
    yield from _emulator_in_a_thread(socket=False)


@pytest.fixture
def emulator_socket_thread():
    """:func:`emulator_thread` listening on a local TCP port: ``(emulator, socket:// URL)``."""
    yield from _emulator_in_a_thread(socket=True)


@pytest.fixture
def qt_settings(tmp_path, monkeypatch):
    """QSettings (and the application's data folder, where blind sessions are autosaved) in a
    temporary folder, so GUI tests never read or write a user's session."""
    from PySide6 import QtCore

    monkeypatch.setenv("XDG_DATA_HOME", str(tmp_path / "data"))
    QtCore.QCoreApplication.setOrganizationName("tactile-tuner-tests")
    QtCore.QCoreApplication.setApplicationName("tactile-tuner-tests")
    QtCore.QSettings.setDefaultFormat(QtCore.QSettings.Format.IniFormat)
    QtCore.QSettings.setPath(
        QtCore.QSettings.Format.IniFormat,
        QtCore.QSettings.Scope.UserScope,
        str(tmp_path / "settings"),
    )
    return tmp_path / "settings"


@pytest.fixture
def emulator(tmp_path):
    emulators = []

    def start(*args):
        emu = Emulator(tmp_path, *args)
        emulators.append(emu)
        return emu

    yield start
    for emu in emulators:
        emu.kill()


@pytest.fixture(scope="session")
def firmware(tmp_path_factory):
    """The reference firmware's ELF and the simavr harness, built once."""
    from .firmware_support import build, require

    require("elf")
    require("sim")
    out = tmp_path_factory.mktemp("firmware")
    return build("all", out), build("sim", out)


@pytest.fixture
def sim(firmware, tmp_path):
    """The firmware running in simavr on a pseudo-terminal."""
    from .firmware_support import simulation

    yield from simulation(firmware, tmp_path)


@pytest.fixture
def window(qtbot, qt_settings):
    """The tuner's main window at 1280 x 720, its stream a thread of this process, streaming
    before the test starts (a test file may define a window of its own)."""
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False, process=False)  # the stream as a thread: quicker
    qtbot.addWidget(win)
    win.resize(1280, 720)
    win.show()
    qtbot.waitExposed(win)
    qtbot.waitUntil(lambda: win.device.stats.frames > 5, timeout=10_000)
    yield win
    win.confirm = lambda title, text: True
    win.close()
