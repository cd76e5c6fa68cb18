"""Choosing and keeping an audio output device: ``audio:`` opens sounddevice's default output,
a device is named by its index when its name is digits or shared, and a device that is busy,
cannot start or is lost under a stream is one line naming it (a LinkError, never a traceback),
with the device let go."""

import os
import subprocess
import sys

import pytest

from tactile_core.device.audio import AudioLink, audio_outputs
from tactile_core.device.link import LinkError
from tactile_core.device.profile import default_profile, profile_from_dict

from .audio_fake import PortAudioError, card, fake_audio
from .audio_support import require_audio


def profile(channels=8, **extra):
    data = default_profile().to_dict()
    data.update(name=f"audio-{channels}", columns=channels, rows=1, **extra)
    return profile_from_dict(data)


class DevicePair:
    """sounddevice's ``default.device``: an (input, output) pair that indexes, not a list."""

    def __init__(self, input_device, output_device):
        self._pair = [input_device, output_device]

    def __getitem__(self, index):
        return self._pair[{"input": 0, "output": 1}.get(index, index)]


def test_audio_colon_opens_the_default_output_device_sounddevice_names(monkeypatch):
    sd, _ = fake_audio(monkeypatch, devices=[card("Speakers", 2), card("USB 8ch", 8)])
    sd.default.device = DevicePair(-1, 1)
    link = AudioLink("audio:", profile(8))
    assert link.device["name"] == "USB 8ch"
    link.close()


def test_audio_colon_opens_the_default_device_through_portaudio(tmp_path):
    """The real sounddevice, on an ALSA configuration whose only PCM is the default."""
    require_audio()
    config = tmp_path / "asound.conf"
    config.write_text("</usr/share/alsa/alsa.conf>\npcm.tactnull {\n    type null\n}\n")
    code = (
        "from tactile_core.device._audio_url import find_device, load_sounddevice\n"
        "print(find_device(load_sounddevice(), '')['name'])\n"
    )
    env = {**os.environ, "ALSA_CONFIG_PATH": str(config)}
    done = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=60
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "tactnull"


@pytest.mark.parametrize("name", ["²", "٠", "１"])
def test_only_ascii_digits_name_a_device_by_its_index(monkeypatch, name):
    fake_audio(monkeypatch)
    with pytest.raises(LinkError) as caught:
        AudioLink(f"audio:{name}", profile(2))
    assert str(caught.value).startswith(f"no audio output device {name!r}; the output devices")


def test_an_ambiguous_name_says_to_use_the_index_and_lists_each_device(monkeypatch):
    fake_audio(monkeypatch, devices=[card("Speakers", 2), card("Speakers", 8), card("USB", 8)])
    with pytest.raises(LinkError) as caught:
        AudioLink("audio:Speakers", profile(2))
    message = str(caught.value)
    assert "'Speakers' is ambiguous: it matches 'Speakers', 'Speakers'" in message
    assert "by its index (audio:N)" in message
    assert "0: 'Speakers' (ALSA): at most 2 output channels" in message
    assert "1: 'Speakers' (ALSA): at most 8 output channels" in message


def test_the_device_box_lists_a_shared_or_digit_name_by_index_and_each_opens(monkeypatch):
    devices = [card("Speakers", 2), card("Speakers", 8), card("2", 8), card("USB", 8)]
    fake_audio(monkeypatch, devices=devices)
    urls = [url for url, _ in audio_outputs()]
    assert urls == ["audio:0", "audio:1", "audio:2", "audio:USB"]
    for index, url in enumerate(urls):
        link = AudioLink(url, profile(2))
        assert link.device["index"] == index  # the device listed, not another
        link.close()


def test_a_device_another_program_holds_is_refused_as_busy(monkeypatch):
    sd, _ = fake_audio(monkeypatch)

    def busy(**kwargs):  # PortAudio's paDeviceUnavailable, as sounddevice raises it
        raise PortAudioError("Device unavailable", -9985)

    monkeypatch.setattr(sd, "check_output_settings", busy)
    with pytest.raises(LinkError) as caught:
        AudioLink("audio:USB", profile(8))
    message = str(caught.value)
    assert "audio device 'USB 8ch' is busy or unavailable" in message
    assert "cannot play" not in message  # not a matter of its channels or samplerate


def test_a_stream_that_opens_but_cannot_start_lets_go_of_the_device(monkeypatch):
    sd, _ = fake_audio(monkeypatch)
    opened = []
    make = sd.OutputStream

    def failing(**kwargs):
        stream = make(**kwargs)

        def start():
            raise PortAudioError("Unanticipated host error", -9999)

        stream.start = start
        opened.append(stream)
        return stream

    monkeypatch.setattr(sd, "OutputStream", failing)
    with pytest.raises(LinkError, match="cannot open audio device 'USB 8ch'"):
        AudioLink("audio:USB", profile(8))
    assert len(opened) == 1 and opened[0].closed


def test_a_profile_of_the_wrong_type_is_refused_naming_it(monkeypatch):
    fake_audio(monkeypatch)
    with pytest.raises(TypeError, match="profile must be a DeviceProfile, got str"):
        AudioLink("audio:USB", "belt-8")


def test_a_stream_portaudio_has_lost_is_a_status_line_not_a_traceback(monkeypatch):
    """sounddevice's ``active`` raises PortAudioError for a stream PortAudio lost (the
    streamer took it for a bug: 'internal error', a traceback and exit 70, no reconnect)."""
    from tactile_core.device.wire import encode_frame

    sd, _ = fake_audio(monkeypatch)
    link = AudioLink("audio:USB", profile(8))
    stream = sd.streams[-1]

    class Lost(type(stream)):
        @property
        def active(self):
            raise PortAudioError("Bad stream pointer", -9988)

        @active.setter
        def active(self, value):
            pass

    stream.__class__ = Lost
    for call in (lambda: link.write(encode_frame(0, [1] * 8)), link.read):
        with pytest.raises(LinkError, match="audio device stopped: 'USB 8ch'"):
            call()
    link.close()
    assert stream.closed
