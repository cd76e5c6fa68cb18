"""``--reconnect`` waits for an array that is not plugged in yet, as it waits for one unplugged
later (new-user pass: the stream exited at once with "no such port")."""

import os
import subprocess

from .emulator_support import CLI


def test_reconnect_waits_for_a_port_that_appears_after_the_stream_started(tmp_path, emulator):
    port = tmp_path / "array"  # not there yet: a symlink to the emulator's pty comes later
    proc = subprocess.Popen(
        [*CLI, "stream", "--device", str(port), "--shape", "circle:2.5,3,2", "--method", "AS",
         "--reconnect", "--seconds", "60"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        waiting = proc.stderr.readline()
        assert "no such port" in waiting and "waiting for it (--reconnect" in waiting, waiting
        emu = emulator()
        os.symlink(emu.path, port)  # the array is plugged in
        for line in proc.stderr:  # the stream opens it and streams
            if line.startswith("[streaming]"):
                break
        else:
            raise AssertionError(f"the stream never streamed (exit {proc.poll()})")
        proc.send_signal(2)  # Ctrl-C: all off, a report
        proc.communicate(timeout=30)
        report, _ = emu.finish()
        assert (
            report["frames"] > 0
            and report["last_levels"]
            and not any(any(row) for row in report["last_levels"])
        )  # frames arrived, and the last one turned everything off
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate(timeout=10)


def test_without_reconnect_a_missing_port_ends_the_stream_at_once(tmp_path):
    out = subprocess.run(
        [*CLI, "stream", "--device", str(tmp_path / "array"), "--shape", "circle:2.5,3,2",
         "--method", "AS", "--seconds", "60"],
        capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert out.returncode == 1 and "no such port" in out.stderr and "waiting" not in out.stderr
