"""Felt-amplitude rendering: with a motor response curve, mu and gamma act on felt amplitude
and the array gets the curve's inverse."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import tactile_core as tc
from tactile_core.device.profile import default_profile, profile_from_dict
from tactile_core.rendering.scene import Scene

from .helpers import align
from .test_streamer import CIRCLE, run

PALM = default_profile()  # response: drive 0 .2 .3 .4 .6 .8 1 -> output 0 0 .3 .55 .78 .92 1


def test_the_inverse_of_the_palm_arrays_response_worked_by_hand():
    felt = [0.0, 0.15, 0.3, 0.5, 0.85, 1.0]
    # 0.15 on the segment (0.2, 0) - (0.3, 0.3): 0.2 + 0.15 / 0.3 x 0.1 = 0.25;
    # 0.5 on (0.3, 0.3) - (0.4, 0.55): 0.3 + 0.2 / 0.25 x 0.1 = 0.38;
    # 0.85 on (0.6, 0.78) - (0.8, 0.92): 0.6 + 0.07 / 0.14 x 0.2 = 0.7.
    expected = [0.0, 0.25, 0.3, 0.38, 0.7, 1.0]
    np.testing.assert_allclose(PALM.drive_for(felt), expected)
    assert [PALM.drive_for1(f) for f in felt] == pytest.approx(expected)
    # Just above nothing: the end of the dead zone, where the motor starts.
    assert PALM.drive_for1(1e-9) == pytest.approx(0.2)


def test_flat_parts_and_a_curve_that_never_reaches_one():
    data = PALM.to_dict()
    data["response"] = {"drive": [0, 0.5, 0.8, 1.0], "output": [0, 0.6, 0.9, 0.9]}
    p = profile_from_dict(data)
    # The least drive that gives 0.9 is 0.8 (not anywhere on the flat top), and nothing past
    # the curve's top exists: full drive.
    assert p.drive_for1(0.9) == pytest.approx(0.8) and p.drive_for1(0.95) == 1.0
    np.testing.assert_allclose(p.drive_for([0.9, 0.95, 0.3]), [0.8, 1.0, 0.25])


@given(st.floats(0, 1))
def test_the_inverse_undoes_the_response_and_scalar_equals_vector(f):
    d = PALM.drive_for1(f)
    assert d == pytest.approx(float(PALM.drive_for(f)), abs=1e-12)
    assert float(PALM.felt(d)) == pytest.approx(f, abs=1e-12)


def test_without_a_response_curve_nothing_changes():
    data = PALM.to_dict()
    data.pop("response", None)
    p = profile_from_dict(data)
    np.testing.assert_array_equal(p.drive_for([0.0, 0.3, 1.0]), [0.0, 0.3, 1.0])
    assert p.drive_for1(0.3) == 0.3


def test_the_streamer_sends_the_drive_for_the_felt_amplitude():
    scene = Scene(CIRCLE, "AS", mu=0.2, gamma=0.6, rate_hz=100.0, dither=False, felt_domain=True)
    frames, _ = run(scene, 120)
    _, corrected = tc.render_frames(scene.trace(), "AS", sampling=scene.sampling(), mu=0.2,
                                    gamma=0.6, n_frames=250)  # fmt: skip
    expected = tc.quantize(PALM.drive_for(corrected), 23).reshape(250, 30)
    lit = frames[:-1]
    assert align([f[2] for f in lit], expected) >= len(lit) - 1
    # and not what the drive domain would send
    plain = tc.quantize(corrected, 23).reshape(250, 30)
    with pytest.raises(AssertionError, match="is not a rendering"):
        align([f[2] for f in lit if f[2].any()], plain)


def test_a_preset_keeps_the_domain(tmp_path):
    from tactile_core.files.presets import Preset, load_preset, save_preset

    scene = Scene(CIRCLE, "IM", felt_domain=True)
    path = save_preset(Preset(scene), tmp_path / "felt.json")
    assert load_preset(path).scene.felt_domain is True
    with pytest.raises(ValueError, match="felt_domain must be true or false"):
        Scene(CIRCLE, felt_domain="yes")


@pytest.mark.usefixtures("qt_settings")
def test_the_tuner_switches_the_domain_and_plots_both(qtbot):
    from tactile_tuner.window import MainWindow

    win = MainWindow(restore=False)
    qtbot.addWidget(win)
    win.show()
    check = win.controls.correction.felt_domain_check
    qtbot.waitUntil(check.isEnabled, timeout=5000)  # the palm array has a response curve
    win.state.update(shape=CIRCLE, method="CT", mu=0.0, gamma=1.0, dither=False)
    check.click()
    assert win.state.scene.felt_domain
    qtbot.waitUntil(lambda: "(felt)" in win.tune.correction.plotItem.titleLabel.text, timeout=3000)
    # mu 0.5 on felt amplitude is drive 0.38 (worked above), level round(8.36) = 8.
    # At mu 0 the first lit level is the motor's start: drive 0.2, level round(4.4) = 4.
    qtbot.waitUntil(lambda: win.tune.correction.steps.getData()[1][1] == pytest.approx(4 / 22),
                    timeout=3000)  # fmt: skip
    win.state.update(mu=0.5)
    qtbot.waitUntil(lambda: win.tune.correction.steps.getData()[1][1] == pytest.approx(8 / 22),
                    timeout=3000)  # fmt: skip
    assert win.tune.correction.steps.getData()[1][-1] == pytest.approx(1.0)
    check.click()
    assert not win.state.scene.felt_domain
    qtbot.waitUntil(
        lambda: "(felt)" not in win.tune.correction.plotItem.titleLabel.text, timeout=3000
    )
    win.close()
