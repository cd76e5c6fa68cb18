"""Shared test set-up: offscreen Qt, deterministic hypothesis, numpy errors as exceptions."""

import os
import threading

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

import pytest
from hypothesis import HealthCheck, settings

settings.register_profile(
    "default",
    deadline=None,
    derandomize=True,
    max_examples=150,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile("thorough", deadline=None, max_examples=2000)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "default"))


@pytest.fixture
def emulator_thread():
    """A device emulator on a pseudo-terminal, receiving in a thread: ``(emulator, path)``."""
    from tactile_core.emulator import Emulator

    emulator = Emulator()
    path = emulator.open()
    stop = threading.Event()
    thread = threading.Thread(target=emulator.run, args=(stop.is_set,), daemon=True)
    thread.start()
    yield emulator, path
    stop.set()
    thread.join(2)
    emulator.close()
