"""``tactile measure``: the contract's --simulate call, --out into a profile that the rest of
the tool then calls measured, the real-time run against the simulated sensor on the simulated
array (the input stand-in), and usage errors."""

import json

import numpy as np
import pytest

from tactile_core.cli import main
from tactile_core.device.profile import load_profile


def run(capsys, *args):
    code = main(["measure", *args])
    out, err = capsys.readouterr()
    return code, out, err


def test_simulate_json_gives_the_contracts_medians(capsys):
    code, out, err = run(capsys, "--simulate", "--tau-up-ms", "20", "--tau-down-ms", "50",
                         "--delay-ms", "8", "--noise", "0.05", "--seed", "3", "--json")  # fmt: skip
    assert code == 0, err
    got = json.loads(out)
    assert got["tau_up_ms"] == pytest.approx(20.0, rel=0.1)
    assert got["tau_down_ms"] == pytest.approx(50.0, rel=0.1)
    assert got["delay_ms"] == pytest.approx(8.0, abs=1.0)
    assert len(got["tactors"]) == 30  # the palm array, every tactor: the median over them
    assert "14.0 s of stimulus per tactor" in err and "7.0 min" in err


def test_simulate_defaults_are_the_palm_estimates(capsys):
    code, out, _ = run(capsys, "--simulate", "--tactors", "r0c0,r5c4", "--json")
    got = json.loads(out)
    assert code == 0
    assert got["tau_up_ms"] == pytest.approx(30.0, rel=0.1)
    assert got["tau_down_ms"] == pytest.approx(60.0, rel=0.1)
    assert got["delay_ms"] == pytest.approx(5.0, abs=1.0)
    assert [t["name"] for t in got["tactors"]] == ["r0c0", "r5c4"]


def test_simulate_prints_a_line_per_tactor_without_json(capsys):
    code, out, _ = run(capsys, "--simulate", "--tactors", "7", "--quick")
    assert code == 0
    assert "8.0 s of stimulus per tactor" in out
    assert "r1c2: spin-up " in out and "median over 1 tactor: spin-up" in out


def test_out_writes_a_measured_profile_the_render_command_calls_measured(capsys, tmp_path):
    out_path = tmp_path / "palm-measured.json"
    code, _, err = run(capsys, "--simulate", "--tau-up-ms", "15", "--tau-down-ms", "40",
                       "--tactors", "0,1", "--out", str(out_path))  # fmt: skip
    assert code == 0, err
    profile = load_profile(out_path)
    assert profile.name == "palm-5x6"
    up, down = profile.motor.taus(30)
    assert up[0] == pytest.approx(0.015, rel=0.1) and down[1] == pytest.approx(0.040, rel=0.1)
    assert up[29] == pytest.approx(0.030)  # not measured: the profile's estimate stays
    assert profile.motor.measured
    assert "measured" in profile.motor.describe()
    frames = tmp_path / "frames.npz"
    render = ["render", "--shape", "line:0.5,0.5,4.5,5.5", "--method", "AS"]
    render += ["--profile", str(out_path), "--compensate-motors", "--out", str(frames)]
    assert main(render) == 0
    said = capsys.readouterr().out
    assert "measured 20" in said and "estimate" not in said


def test_render_says_estimate_for_the_bundled_palm_profile(capsys, tmp_path):
    frames = tmp_path / "frames.npz"
    assert main(["render", "--shape", "line:0.5,0.5,4.5,5.5", "--method", "AS",
                 "--compensate-motors", "--out", str(frames)]) == 0  # fmt: skip
    assert "(estimate)" in capsys.readouterr().out


def test_real_time_run_on_the_simulated_array_with_the_simulated_sensor(capsys):
    # --input sim: the input stand-in, recording in real time what the simulated array plays
    code, out, err = run(capsys, "--input", "sim", "--device", "sim", "--profile", "grid-3x3",
                         "--tactors", "r0c0", "--quick", "--tau-up-ms", "25", "--json")  # fmt: skip
    assert code == 0, err
    got = json.loads(out)
    assert got["tau_up_ms"] == pytest.approx(25.0, rel=0.1)
    assert got["tau_down_ms"] == pytest.approx(60.0, rel=0.1)
    # frames for now on the simulated array: the frame's write time is when it applies
    assert got["delay_ms"] == pytest.approx(5.0, abs=1.0)
    assert "measuring r0c0 (6.3 s)" in err
    curve = np.array(got["response"]["output"])
    assert curve[-1] == 1.0 and np.all(np.diff(curve) >= 0)


@pytest.mark.parametrize(
    "args, says",
    [
        (["--simulate", "--input", "sim"], "--simulate runs without --input and --device"),
        (["--input", "audio:"], "give --input URL and --device URL"),
        (["--simulate", "--tactors", "r9c9"], "--tactors: 'r9c9' is not a tactor of palm-5x6"),
        (["--simulate", "--tactors", "1,1"], "--tactors names a tactor twice"),
        (["--simulate", "--tau-up-ms", "0"], "--tau-up-ms must be within [0.5, 2000]"),
        (["--input", "audio:", "--device", "sim", "--noise", "0.1"],
         "--noise sets the simulated sensor"),
        (["--simulate", "--out", "x.csv"], "--out"),
    ],
)  # fmt: skip
def test_usage_errors_name_the_option(capsys, args, says):
    code, _, err = run(capsys, *args)
    assert code == 2
    assert says in err


def test_simulated_sensor_needs_the_simulated_array(capsys, emulator_socket_thread):
    _, url = emulator_socket_thread
    code, _, err = run(capsys, "--input", "sim", "--device", url, "--yes")
    assert code == 1
    assert "the simulated sensor ('sim') sits on the simulated array" in err


def test_an_audio_input_that_is_not_there_is_listed(capsys):
    pytest.importorskip("sounddevice", exc_type=OSError)
    code, _, err = run(capsys, "--input", "audio:no-such-interface-xyz", "--device", "sim",
                       "--yes")  # fmt: skip
    assert code == 1
    assert "audio input 'no-such-interface-xyz' not found; the inputs are" in err


def test_the_trade_and_the_felt_read_out_say_measured_for_a_measured_profile(capsys, tmp_path):
    from tactile_core.bench import Target, felt_readout
    from tactile_core.rendering.scene import Scene

    palm = load_profile("palm-5x6")
    assert Target.of(palm).motor_source == "estimate"
    out_path = tmp_path / "palm-measured.json"
    assert main(["measure", "--simulate", "--tactors", "0", "--out", str(out_path)]) == 0
    measured = load_profile(out_path)
    source = Target.of(measured).motor_source
    assert source.startswith("measured 20") and len(source) == len("measured 2026-05-01")
    scene = Scene(tc_line(), method="AS", duration_s=1.0)
    assert felt_readout(scene, measured).motor_source == source
    assert felt_readout(scene, palm).motor_source == "estimate"


def tc_line():
    import tactile_core as tc

    return tc.Line((0.5, 1.84), (4.5, 4.16))
