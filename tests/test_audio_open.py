"""Opening an audio device is bounded: one that never opens (ALSA's file plugin writing into a
named pipe that nobody reads waits in open(2)) is given up with a line that names it and says
what to check, and ``tactile stream --seconds`` bounds the whole run."""

import os
import subprocess
import sys
import threading

import pytest

from tactile_core.device import audio
from tactile_core.device.audio import AudioLink
from tactile_core.device.link import LinkError, open_link
from tactile_core.device.profile import default_profile, profile_from_dict

from .audio_fake import fake_audio
from .audio_support import DEVICE, require_audio


def profile(channels=8):
    data = default_profile().to_dict()
    data.update(name=f"audio-{channels}", columns=channels, rows=1)
    return profile_from_dict(data)


@pytest.fixture
def hanging(monkeypatch):
    """A fake sounddevice whose ``call`` ("check_output_settings" or "OutputStream") waits
    until the test lets it go (as open(2) on a pipe without a reader does)."""
    release = threading.Event()

    def make(call):
        sd, _ = fake_audio(monkeypatch)
        real = getattr(sd, call)

        def waits(*args, **kwargs):
            release.wait(60)
            return real(*args, **kwargs)

        setattr(sd, call, waits)
        return sd

    yield make
    release.set()  # the openings given up on finish, and leave nothing waiting
    for thread in list(audio._STUCK):
        thread.join(10)
        assert not thread.is_alive()


@pytest.mark.parametrize("call", ["check_output_settings", "OutputStream"])
def test_a_device_that_never_opens_is_given_up_naming_it(hanging, call):
    hanging(call)
    with pytest.raises(LinkError) as caught:
        AudioLink("audio:USB", profile(8), open_timeout_s=0.2)
    message = str(caught.value)
    assert "audio device 'USB 8ch' did not open within 0.2 s" in message
    assert "named pipe without a reader" in message  # what to check
    # asked again while that opening still waits: refused at once, not a second waiter
    with pytest.raises(LinkError, match="an earlier opening still waits"):
        AudioLink("audio:USB", profile(8), open_timeout_s=0.2)
    assert len(audio._STUCK) == 1


def test_open_link_passes_the_bound_on(hanging):
    hanging("check_output_settings")
    with pytest.raises(LinkError, match=r"did not open within 0\.1 s"):
        open_link("audio:USB", profile(8), open_timeout_s=0.1)


@pytest.mark.parametrize("bad", [0, -1.0, float("nan"), float("inf"), "5", None])
def test_the_open_timeout_must_be_positive_seconds(monkeypatch, bad):
    fake_audio(monkeypatch)
    with pytest.raises(ValueError, match=r"^open_timeout_s must be a positive number of seconds"):
        AudioLink("audio:USB", profile(8), open_timeout_s=bad)


def test_tactile_stream_into_a_pipe_nobody_reads_ends_within_its_seconds(tmp_path):
    # ALSA's file plugin opens its file when PortAudio checks the settings: on a named pipe
    # without a reader that open(2) waited for 10 minutes, with no output, --seconds unheeded.
    require_audio()
    pipe = tmp_path / "nobody-reads.pipe"
    os.mkfifo(pipe)
    config = tmp_path / "asound.conf"
    config.write_text(
        "</usr/share/alsa/alsa.conf>\n"
        f'pcm.{DEVICE} {{\n    type file\n    slave.pcm {{ type null }}\n    file "{pipe}"\n'
        '    format "raw"\n}\n'
    )
    proc = subprocess.run(
        [sys.executable, "-m", "tactile_core.cli", "stream", "--device", f"audio:{DEVICE}",
         "--profile", "belt-8", "--shape", "line:0,0,7,0", "--method", "BA", "--seconds", "1"],
        env={**os.environ, "ALSA_CONFIG_PATH": str(config)},
        capture_output=True, text=True, timeout=60,  # a bound for a loaded machine
    )  # fmt: skip
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert f"audio device '{DEVICE}' did not open within 1 s" in proc.stderr
    assert "Traceback" not in proc.stderr
