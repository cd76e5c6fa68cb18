"""Bad input to the measurement, on simulated signals: no signal, clipping, the wrong channel,
mains hum, a tactor that does not move, two tactors moving, the sensor on another tactor. Each
ends with an error or a warning that names the cause and what to check, and nothing is written
to the profile."""

import json

import pytest

from tactile_core.device.measure import save_measured, simulate_measurement
from tactile_core.device.profile import default_profile, load_profile

CELL = 7  # r1c2: inside the palm array, eight neighbours


def measure_into(tmp_path, **fault):
    """Measure CELL with ``fault``; the result and whether a profile was written."""
    profile = default_profile()
    result = simulate_measurement(profile, cells=[CELL], noise=0.02, seed=4, **fault)
    out = tmp_path / "measured.json"
    why = save_measured(out, profile, result)
    return result, why, out.exists()


def only_failure(result) -> str:
    assert list(result.failures) == ["r1c2"]
    return result.failures["r1c2"]


def test_no_signal_on_the_sensor_says_what_to_check(tmp_path):
    result, why, written = measure_into(tmp_path, amplitude=0.0)
    text = only_failure(result)
    assert "no signal on the sensor" in text
    for check in ("array is on", "cable", "channel", "gain", "touches"):
        assert check in text
    assert "no constants for r1c2" in why and not written


def test_clipping_says_to_turn_the_gain_down(tmp_path):
    result, why, written = measure_into(tmp_path, gain=8.0)
    text = only_failure(result)
    assert "clips" in text and "input gain down" in text
    assert why and not written


def test_sensor_on_another_input_is_named(tmp_path):
    # the sensor is wired to input 2 of a two-input interface; the URL asked for input 1
    result, why, written = measure_into(tmp_path, channels=2, channel=1, input_channel=0)
    text = only_failure(result)
    assert "input 2 of the interface follows the stimulus" in text
    assert "?channel=2" in text
    assert why and not written


def test_mains_hum_is_a_warning_and_blocks_the_profile(tmp_path):
    result, why, written = measure_into(tmp_path, hum=0.3, hum_hz=60.0)
    assert result.failures == {}
    (warning,) = result.warnings
    assert "mains hum at 60 Hz" in warning
    assert "ground loop" in warning and "shielded cable" in warning
    assert "--accept-warnings" in why and not written
    # the constants are still right: hum is stationary and taken off as noise
    (t,) = result.tactors
    assert t.tau_up_s == pytest.approx(0.030, rel=0.1)
    assert t.tau_down_s == pytest.approx(0.060, rel=0.1)


def test_accepting_warnings_writes_the_profile(tmp_path):
    profile = default_profile()
    result = simulate_measurement(profile, cells=[CELL], noise=0.02, seed=4, hum=0.3)
    out = tmp_path / "measured.json"
    assert save_measured(out, profile, result, accept_warnings=True) == ""
    assert json.loads(out.read_text())["motor"]["note"].startswith("measured")


def test_a_tactor_that_does_not_move_is_named_while_its_neighbours_answer(tmp_path):
    result, why, written = measure_into(tmp_path, dead=(CELL,))
    text = only_failure(result)
    assert "tactor r1c2 does not move" in text
    assert "motor" in text and "wiring" in text and "channel order" in text
    assert why and not written


def test_two_motors_on_one_channel_are_found(tmp_path):
    # driving r1c2 also drives r1c3 (a wiring fault): two lines in the spectrum
    result, why, written = measure_into(tmp_path, also={CELL: CELL + 1})
    text = only_failure(result)
    assert "two vibrations while only tactor r1c2 is driven" in text
    assert "wiring" in text and "channel_order" in text
    assert why and not written


def test_sensor_on_another_tactor_names_it(tmp_path):
    result, why, written = measure_into(tmp_path, sensor_on={CELL: CELL + 5})  # on r2c2
    text = only_failure(result)
    assert "the sensor is on tactor r2c2, not on r1c2" in text
    assert "Move the sensor onto r1c2" in text
    assert why and not written


def test_sensor_between_two_tactors_is_a_warning(tmp_path):
    # a sensor that picks up a neighbour almost as well as its own tactor
    result, why, written = measure_into(tmp_path, coupling=0.8)
    assert result.failures == {}
    assert any("it may sit between them" in w for w in result.warnings)
    assert why and not written


def test_a_clean_run_writes_the_measured_constants_per_tactor(tmp_path):
    profile = load_profile("grid-3x3")
    result = simulate_measurement(profile, cells=[0, 4], noise=0.02, seed=1,
                                  tau_up_ms=20.0, tau_down_ms=45.0)  # fmt: skip
    out = tmp_path / "grid.json"
    assert save_measured(out, profile, result) == ""
    data = json.loads(out.read_text())
    up, down = data["motor"]["tau_up_ms"], data["motor"]["tau_down_ms"]
    assert len(up) == len(down) == 9
    assert up[0] == pytest.approx(20.0, rel=0.1) and down[4] == pytest.approx(45.0, rel=0.1)
    # tactors not measured get the median of those measured (the profile had no constants)
    assert up[8] == pytest.approx(20.0, rel=0.1)
    assert data["motor"]["note"].startswith("measured")
    assert [t["name"] for t in data["measured"]["tactors"]] == ["r0c0", "r1c1"]
    assert data["response"]["output"][-1] == 1.0
    measured = load_profile(out)
    assert measured.motor.measured and measured.motor.source == "measured"
    assert measured.response is not None


def test_measuring_a_tactor_more_keeps_the_ones_measured_before(tmp_path):
    out = tmp_path / "grid.json"
    first = load_profile("grid-3x3")
    save_measured(out, first, simulate_measurement(first, cells=[0], seed=1, tau_up_ms=20.0))
    again = load_profile(out)
    save_measured(out, again, simulate_measurement(again, cells=[4], seed=2, tau_up_ms=40.0))
    data = json.loads(out.read_text())
    assert [t["name"] for t in data["measured"]["tactors"]] == ["r0c0", "r1c1"]
    up = data["motor"]["tau_up_ms"]
    assert up[0] == pytest.approx(20.0, rel=0.1) and up[4] == pytest.approx(40.0, rel=0.1)
    assert "2 of 9" in data["motor"]["note"]
