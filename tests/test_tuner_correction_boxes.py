"""The mu and gamma boxes show the correction in use, whatever set it: the slider, a preset, a
sender, a value typed. The core accepts any finite gamma above 0 (the contract); the gamma
slider spans 0.1-10 on a log scale and sits at its end beyond, the box takes the value itself."""

import json

import pytest
from PySide6 import QtCore

Key = QtCore.Qt.Key


@pytest.mark.parametrize(("gamma", "shown", "slider"), [(50, "50.00", 1000), (0.05, "0.05", 0)])
def test_a_presets_gamma_beyond_the_slider_shows_in_the_gamma_box(window, tmp_path, gamma,
                                                                  shown, slider):  # fmt: skip
    # The title said gamma 50.00 while the box read 10.00 (0.10 for 0.05), its range's end.
    path = tmp_path / "edited.json"
    assert window.files.save_preset_file(path)
    preset = json.loads(path.read_text())
    preset["gamma"] = gamma
    path.write_text(json.dumps(preset))
    assert window.files.load_preset_file(path)
    correction = window.controls.correction
    assert window.state.scene.gamma == gamma
    assert correction.gamma_spin.value() == gamma and correction.gamma_spin.text() == shown
    assert correction.gamma_slider.value() == slider  # at its end: 0.1-10 on a log scale
    assert window.windowTitle().endswith(f"gamma {shown}")
    correction.mu_spin.setValue(0.5)  # another control: the gamma in use stays, and is shown
    assert window.state.scene.gamma == gamma and correction.gamma_spin.text() == shown


def test_a_gamma_typed_beyond_the_slider_plays_as_typed(window, qtbot):
    # The box's range was the slider's: 50 typed became 10.
    spin = window.controls.correction.gamma_spin
    spin.setFocus()
    spin.selectAll()
    qtbot.keyClicks(spin, "50")
    qtbot.keyClick(spin, Key.Key_Return)
    assert window.state.scene.gamma == 50.0 and spin.text() == "50.00"
    spin.setFocus()
    spin.selectAll()
    qtbot.keyClicks(spin, "0.0005")
    qtbot.keyClick(spin, Key.Key_Return)
    assert window.state.scene.gamma == 0.0005 and spin.text() == "0.0005"


def test_a_gamma_of_zero_typed_is_not_taken(window, qtbot):
    # gamma must be above 0 (the contract): 0 is not a value of the box, and nothing changes.
    spin = window.controls.correction.gamma_spin
    spin.setFocus()
    spin.selectAll()
    qtbot.keyClicks(spin, "0")
    qtbot.keyClick(spin, Key.Key_Return)
    assert window.state.scene.gamma == 0.7
    # as -1 or 1e400 are not: no error dialog (0 opened one, the others none), and the box
    # shows the gamma in use again when left (it kept 0.00 while 0.70 played)
    assert window.last_error == ""
    window.tabs.setFocus()
    assert spin.value() == 0.7 and spin.text() == "0.70"


def test_enter_in_a_box_keeps_the_value_in_use_not_its_rounding(window, qtbot):
    # The box writes gamma 0.14286 as 0.143; Enter without typing must not set 0.143.
    window.state.update(mu=0.33333, gamma=1 / 7)
    correction = window.controls.correction
    assert (correction.mu_spin.text(), correction.gamma_spin.text()) == ("0.333", "0.143")
    for spin in (correction.mu_spin, correction.gamma_spin):
        spin.setFocus()
        qtbot.keyClick(spin, Key.Key_Return)
    assert (window.state.scene.mu, window.state.scene.gamma) == (0.33333, 1 / 7)


def test_a_tiny_or_huge_gamma_is_written_with_three_significant_digits(window):
    correction = window.controls.correction
    for gamma, shown in ((1.234e-5, "1.23e-05"), (2.5e7, "2.5e+07"), (12345.6789, "12345.679")):
        window.state.update(gamma=gamma)
        assert correction.gamma_spin.value() == gamma
        assert correction.gamma_spin.text() == shown
        assert window.windowTitle().endswith(f"gamma {shown}")


def test_the_gamma_box_steps_in_its_values_second_digit_and_never_reaches_zero(window):
    spin = window.controls.correction.gamma_spin
    window.state.update(gamma=50.0)
    spin.stepBy(1)
    assert window.state.scene.gamma == pytest.approx(51.0)
    window.state.update(gamma=0.7)
    spin.stepBy(1)
    assert window.state.scene.gamma == pytest.approx(0.71)
    window.state.update(gamma=0.01)
    spin.stepBy(-1)
    assert window.state.scene.gamma == pytest.approx(0.0099) and spin.text() == "0.0099"
    for _ in range(100):  # 0.0098 ... 0.0010 by 0.0001, then by 0.00001
        spin.stepBy(-1)
    assert 0.0 < window.state.scene.gamma < 0.001


def test_the_correction_boxes_are_no_wider_for_their_range(window):
    # A range up to 1.8e308 would size the box for "1.8e+308": it stays as wide as "10.000".
    correction = window.controls.correction
    assert correction.gamma_spin.sizeHint().width() <= correction.mu_spin.sizeHint().width() + 4


@pytest.mark.parametrize(("box", "typed", "said"), [
    ("mu_spin", "-1", "mu must be within [0, 1], got -1"),
    ("mu_spin", "1e400", "mu must be within [0, 1], got 1e400"),
    ("gamma_spin", "0", "gamma must be a finite number above 0, got 0"),
    ("gamma_spin", "-1", "gamma must be a finite number above 0, got -1"),
])  # fmt: skip
def test_a_value_typed_that_a_box_cannot_take_is_named_in_the_status_line(window, qtbot, box,
                                                                         typed, said):  # fmt: skip
    # docs/bad-input.md: a value from the tuner's fields is refused with one line naming the
    # parameter and the value; the boxes went back to the value in use without a word.
    spin = getattr(window.controls.correction, box)
    before = window.state.scene
    spin.setFocus()
    spin.selectAll()
    qtbot.keyClicks(spin, typed)
    qtbot.keyClick(spin, Key.Key_Return)
    assert window.statusBar().currentMessage() == f"not taken: {said} (the value in use is kept)"
    assert (window.state.scene.mu, window.state.scene.gamma) == (before.mu, before.gamma)
    assert window.last_error == ""  # a line, not a dialog
