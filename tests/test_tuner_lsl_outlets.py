"""The tuner's Lab Streaming Layer setting when liblsl cannot open the outlets or another
program holds the tuner's source id: the setting shows what is true (off, or the id taken), and
the status line gives the reason once."""

import pylsl
import pytest

from .test_tuner_serve import make_window

pytestmark = pytest.mark.usefixtures("qt_settings")
WAIT_MS = 15_000


def test_tuner_lsl_that_cannot_open_turns_the_setting_off_with_one_reason(qtbot, monkeypatch):
    """The status line said 'Lab Streaming Layer: Lab Streaming Layer: …' once the outlets'
    error named LSL itself."""

    def refuse(*args, **kwargs):
        raise RuntimeError("could not create stream outlet.")

    monkeypatch.setattr(pylsl, "StreamOutlet", refuse)
    win = make_window(qtbot, process=False)
    try:
        win.serve.set_lsl(True)
        qtbot.waitUntil(lambda: win.serve.lsl_status == "off" and bool(win.last_error),
                        timeout=WAIT_MS)  # fmt: skip
        assert win.last_error.startswith("Lab Streaming Layer: cannot open the outlets")
        assert win.last_error.count("Lab Streaming Layer") == 1
        assert not win.serve.lsl_markers and win.serve_panel.lsl_label.text().endswith("off")
    finally:
        win.close()


def test_tuner_lsl_beside_another_program_says_which_source_id_it_took(qtbot):
    """A second program with the tuner's source id (another tuner, a tactile serve --lsl): the
    tuner's outlets take their own, and the status line says so."""
    from tactile_core.device.profile import default_profile
    from tactile_core.serve import LslOutlets

    held = LslOutlets(default_profile())
    win = make_window(qtbot, process=True)
    try:
        said = []
        win.serve.message_posted.connect(lambda text, _ms: said.append(text))
        win.serve.set_lsl(True)
        qtbot.waitUntil(lambda: win.serve.lsl_status.endswith("-markers"), timeout=WAIT_MS)
        mine = win.serve.lsl_status.removesuffix("-markers")
        assert mine != held.source_id
        assert any(f"this one's source id is {mine}" in text for text in said)
    finally:
        win.close()
        held.close()
