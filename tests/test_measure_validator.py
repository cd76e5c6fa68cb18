"""The validator: the sensor's onset of each presentation beside its commanded time, from a
script (open_array(validate=...)) and from tactile serve --validate, to a CSV and to LSL.

The simulated sensor sits on r0c0 of the simulated array; its motors spin up with 30 ms after a
5 ms delay, and the palm response gives a tenth of full vibration at drive 0.2 + 0.1 / 3, so a
full-drive presentation on r0c0 is first felt 5 + 30 ln(1 / (1 - 0.2333)) = 12.97 ms after its
first frame went out."""

import csv
import json
import math
import socket
import subprocess
import sys
import time

import numpy as np
import pylsl
import pytest

import tactile_core as tc
from tactile_core.device.measure import detect_onset, first_order
from tactile_core.experiments.measure import FIELDS
from tactile_core.serve._osc_wire import encode_message

EXPECTED_MS = 5.0 + 30.0 * math.log(1.0 / (1.0 - (0.2 + 0.1 / 3)))
ON_R0C0 = "circle:0.5,0.5,0.1"  # CT keeps r0c0 alone at full drive
ON_R5C4 = "circle:4.5,5.5,0.1"  # the far corner: nothing reaches the sensor


def read_log(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def test_detect_onset_finds_a_first_order_rise_by_hand():
    sr = 8000
    t = np.arange(int(0.6 * sr)) / sr
    rng = np.random.default_rng(0)
    a = 0.3 * first_order(t, [0.2 + 0.004], [1.0], tau_up_s=0.02, tau_down_s=0.05)
    x = a * np.sin(2 * np.pi * 180 * t) + rng.normal(0, 0.001, t.size)
    found = detect_onset(x, sr, command_s=0.2)
    # amplitude 0.3 (1 - exp(-dt / 20 ms)) reaches a tenth of 0.3 after 20 ln(1 / 0.9) ms
    assert (found.onset_s - 0.2) * 1e3 == pytest.approx(4.0 + 20 * math.log(1 / 0.9), abs=0.6)
    assert found.peak == pytest.approx(0.3, rel=0.02)
    silent = detect_onset(rng.normal(0, 0.001, t.size), sr, command_s=0.2)
    assert not silent.found


def test_script_validator_logs_each_onset_beside_its_commanded_time(tmp_path):
    # frames 20 ms ahead: each presentation's time is when the array plays it, exactly
    with tc.open_array("sim", validate="sim", validate_log=tmp_path, lead_ms=20) as array:
        shown = []
        for _ in range(5):
            shown.append(array.play(ON_R0C0, method="CT", duration_s=0.3))
            time.sleep(0.25)  # the stimuli's spacing: the motor runs down between them
        array.play(ON_R5C4, method="CT", duration_s=0.3)
        validator = array.validator
    summary = validator.summary()  # closed with the array: every presentation is in
    assert summary["presentations"] == 6 and summary["detected"] == 5
    assert summary["delay_mean_ms"] == pytest.approx(EXPECTED_MS, abs=1.5)
    assert summary["delay_sd_ms"] < 1.0
    (path,) = tmp_path.glob("validate-*.csv")
    rows = read_log(path)
    assert list(rows[0]) == list(FIELDS)
    for row, presentation in zip(rows, shown):
        assert float(row["commanded_s"]) == pytest.approx(presentation.first_frame_s, abs=1e-6)
        delay = (float(row["detected_s"]) - float(row["commanded_s"])) * 1e3
        assert float(row["delay_ms"]) == pytest.approx(delay, abs=0.002)
    assert rows[5]["detected_s"] == "" and "no vibration detected" in rows[5]["note"]
    assert "validator: 5 of 6 presentations detected" in validator.summary_line()


def test_validator_markers_on_lsl_are_stamped_with_the_detected_time(tmp_path):
    offset = pylsl.local_clock() - time.perf_counter()
    with tc.open_array("sim", validate="sim", validate_log=tmp_path / "v.csv", lsl=True,
                       lead_ms=20) as array:  # fmt: skip
        sid = array.validator.outlet.source_id
        found = pylsl.resolve_bypred(f"source_id='{sid}'", 1, 20.0)
        assert found and found[0].name() == "tactile-validation"
        inlet = pylsl.StreamInlet(found[0], max_buflen=60)
        inlet.open_stream(20.0)
        time.sleep(0.2)
        array.play(ON_R0C0, method="CT", duration_s=0.3)
        sample, stamp = inlet.pull_sample(timeout=20.0)
    (row,) = read_log(tmp_path / "v.csv")
    data = json.loads(sample[0])
    assert data["presentation"] == 1 and data["detected"] is True
    assert data["delay_ms"] == pytest.approx(float(row["delay_ms"]), abs=0.01)
    assert stamp == pytest.approx(float(row["detected_s"]) + offset, abs=0.002)


def test_validate_needs_a_sensor_the_array_can_have(tmp_path):
    with pytest.raises(ValueError, match="the sensor must be an audio: URL, 'sim' or a sensor"):
        tc.open_array("sim", validate=42, validate_log=tmp_path)


def test_serve_validate_logs_the_shapes_it_plays(tmp_path):
    log = tmp_path / "serve.csv"
    proc = subprocess.Popen(
        [sys.executable, "-m", "tactile_core.cli", "serve", "--device", "sim", "--osc-port",
         "0", "--validate", "sim", "--validate-log", str(log), "--status-s", "0",
         "--seconds", "4", "--method", "CT"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        first = proc.stdout.readline().strip()
        assert first.startswith("osc://"), first + proc.stderr.read()
        host, port = first[len("osc://") :].rsplit(":", 1)
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
            s.sendto(encode_message("/tactile/shape", [ON_R0C0, 0.3]), (host, int(port)))
        out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 0, err
    assert "validator: 1 of 1 presentations detected" in out
    (row,) = read_log(log)
    assert row["kind"] == "osc-shape"
    assert float(row["delay_ms"]) == pytest.approx(EXPECTED_MS, abs=1.5)


def test_serve_refuses_a_sensor_it_cannot_open_before_serving(capsys, tmp_path):
    from tactile_core.cli import main

    code = main(["serve", "--device", "sim", "--osc-port", "0", "--validate", "/dev/ttyUSB0",
                 "--validate-log", str(tmp_path), "--seconds", "1"])  # fmt: skip
    out, err = capsys.readouterr()
    assert code == 1
    assert "tactile serve: --validate: a sensor's input must be an audio: URL" in err
    assert "osc://" not in out and not list(tmp_path.iterdir())
