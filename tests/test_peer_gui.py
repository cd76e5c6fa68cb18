"""The peer methods in the tuner: chosen under *other* with their parameter, streamed, compared
in any set, and the predicted view."""

import numpy as np
import pytest
from PySide6 import QtCore

import tactile_core as tc
from tactile_core.rendering.percept import predict

from .test_tuner import lit_levels, wait_for_levels, window  # noqa: F401 - the fixture

pytestmark = pytest.mark.usefixtures("qt_settings")


def test_other_methods_and_their_parameter_drive_the_array(window, qtbot):  # noqa: F811
    method_box = window.controls.method
    window.state.update(shape=tc.Circle((2.5, 3.0), 2.0), mu=0.0, gamma=1.0, dither=False)
    combo = method_box.other_combo
    combo.setCurrentIndex(combo.findData("RO"))
    combo.activated.emit(combo.currentIndex())
    assert window.state.scene.method == "RO" and method_box.other_button.isChecked()
    assert method_box.param_spin.isVisible() and method_box.param_label.text() == "r"
    method_box.param_spin.setValue(2.0)
    assert window.state.scene.method == "RO:r=2"
    # RO at r = 2 lights more tactors than any of the paper's methods can (at most 4).
    wait_for_levels(qtbot, window, lambda levels: (levels > 0).sum() > 4)
    qtbot.keyClick(window, QtCore.Qt.Key.Key_3)  # key 3: back to the paper's AS
    assert window.state.scene.method == "AS" and not method_box.param_spin.isVisible()
    assert method_box.other_combo.currentIndex() == -1  # the list shows no method as on
    wait_for_levels(qtbot, window, lambda levels: 0 < (levels > 0).sum() <= 4)
    method_box.other_button.click()  # "other" with nothing chosen: the first of the list
    assert window.state.scene.method == "EN" and method_box.other_combo.currentData() == "EN"


def test_blind_ab_hides_the_other_method_and_its_parameter(window):  # noqa: F811
    window.blind.set_methods(["AS", "GS:sigma=0.8"])
    window.blind.start(seed=3)
    method_box = window.controls.method
    assert method_box.other_combo.currentIndex() == -1 and not method_box.other_combo.isEnabled()
    assert not method_box.param_spin.isVisible()
    window.blind.select_key(2 if window.blind.session.mapping[1].startswith("GS") else 1)
    assert window.state.scene.method == "GS:sigma=0.8"
    assert method_box.other_combo.currentIndex() == -1 and not method_box.param_spin.isVisible()


def test_the_predicted_view_shows_the_centroid_path_and_felt_intensity(window, qtbot):  # noqa: F811
    scene = window.state.scene
    window.state.update(method="EN")
    window.state.set_view_mode("predicted")
    qtbot.waitUntil(lambda: "ripple" in window.tune.curves.plotItem.titleLabel.text, timeout=3000)
    profile = window.device.profile
    expected = predict(scene.shape, "EN", scene.mu, scene.gamma, rate_hz=scene.rate_hz,
                       levels=profile.levels, motor=profile.motor)  # fmt: skip
    title = window.tune.curves.plotItem.titleLabel.text
    assert f"TH 0.2, K 1: ripple {expected.ripple:.2f}" in title and "25 participants" in title
    x, y = window.tune.heatmap.path.getData()
    np.testing.assert_allclose(np.column_stack([x, y]), expected.centroid)
    (line,) = window.tune.curves.listDataItems()
    np.testing.assert_allclose(line.getData()[1], expected.felt)
    window.state.set_view_mode("corrected")
    qtbot.waitUntil(
        lambda: "activation" in window.tune.curves.plotItem.titleLabel.text, timeout=3000
    )
    assert len(window.tune.heatmap.path.getData()[0] or []) == 0


def test_compare_drives_each_method_with_its_own_correction(window, qtbot):  # noqa: F811
    window.state.update(shape=tc.Line((0.5, 1.84), (4.5, 4.16)), mu=0.33, gamma=0.7)
    window.compare.set_methods(["AS", "EN"])
    window.tabs.setCurrentWidget(window.compare)
    heat = window.compare.heatmaps
    qtbot.waitUntil(lambda: all(h.values.any() for h in heat.values()), timeout=3000)
    titles = {m: c.plotItem.titleLabel.text for m, c in window.compare.curves.items()}
    assert "set correction" in titles["AS"] and "no correction" in titles["EN"]
    # EN's column is the raw sqrt of AS's areas: sum of squares 1 inside the hull; AS's column
    # is corrected (mu 0.33 lifts every lit tactor to at least 0.33).
    assert float((heat["EN"].values ** 2).sum()) == pytest.approx(1.0, abs=1e-9)
    lit = heat["AS"].values[heat["AS"].values > 0]
    assert lit.min() >= 0.33 - 1e-12
