"""``tactile serve`` given what it cannot use: senders that dodge the flood guard or write
escape sequences, an IPv6 or empty host, a layout its default method cannot render, a --json
file it cannot write. Each is handled or refused in one line; the operator's terminal shows
what was sent, not what it would do."""

import pytest

from .helpers import run_cli_here
from .serve_support import ServerRig


def run_cli(capsys, *argv, stdout=None):
    """``(status, standard error)``; standard output appended to ``stdout`` if given."""
    code, out, err = run_cli_here(capsys, *argv)
    if stdout is not None:
        stdout.append(out)
    return code, err


@pytest.mark.parametrize("address", ["/tactile/offset", "/tactile/release_everything"])
def test_serve_flood_guard_reads_only_the_exact_off_and_release_addresses(address):
    """Every datagram starting with the bytes '/tactile/off' or '/tactile/release' was read
    whatever the rate: a flood of '/tactile/offset' went round the limit."""
    from pythonosc.osc_message_builder import OscMessageBuilder

    with ServerRig(max_rate_hz=100.0) as rig:  # a bucket of 5 messages
        sock = rig.client._sock
        junk = OscMessageBuilder(address).build().dgram
        for _ in range(200):
            sock.sendto(junk, rig.server.address)
        sock.sendto(OscMessageBuilder("/tactile/off").build().dgram, rig.server.address)
        rig.wait_count("controls", 1)
        s = rig.server.stats
        assert s.flood_dropped > 100
        assert s.unknown + s.flood_dropped == s.datagrams - 1


def test_serve_summary_escapes_what_a_sender_wrote_for_the_terminal():
    """A sender's method name (or address) went raw into the summary printed on the operator's
    terminal: ESC sequences in one could clear it or retitle it."""
    with ServerRig() as rig:
        rig.send("/tactile/method", "\x1b[2J\x1b]0;owned\x07")
        rig.wait_count("refused", 1)
        rig.send("/\x1b[31mred", 1.0)
        rig.wait_count("unknown", 1)
        summary = rig.server.stats.summary()
    assert "\x1b" not in summary and "\x07" not in summary
    assert "last problem: unknown address /\\x1b[31mred" in summary


def test_serve_prints_an_ipv6_address_as_a_url(capsys):
    """The first line was osc://::1:9100, which no URL parser splits into host and port."""
    import socket

    try:
        with socket.socket(socket.AF_INET6, socket.SOCK_DGRAM) as probe:
            probe.bind(("::1", 0))
    except OSError:
        pytest.skip("no IPv6 loopback on this machine")
    out = []
    code, _ = run_cli(capsys, "serve", "--device", "sim", "--host", "::1", "--osc-port", "0",
                      "--seconds", "0.1", "--status-s", "0", stdout=out)  # fmt: skip
    assert code == 0
    first = out[0].splitlines()[0]
    assert first.startswith("osc://[::1]:") and int(first.rsplit(":", 1)[1]) > 0


def test_serve_refuses_an_empty_host(capsys):
    code, err = run_cli(capsys, "serve", "--device", "sim", "--host", "", "--osc-port", "0")
    assert code == 2 and "--host" in err and "Name or service" not in err


def test_serve_on_a_layout_profile_starts_with_its_default_method(capsys):
    """`tactile serve --profile belt-8` refused its own default method (AS needs a grid); the
    default there is BA, AS's weights for any layout, as the tuner falls back to."""
    code, err = run_cli(capsys, "serve", "--device", "sim", "--profile", "belt-8",
                        "--osc-port", "0", "--seconds", "0.1", "--status-s", "0")  # fmt: skip
    assert code == 0 and "serving belt-8 (BA," in err
    code, err = run_cli(capsys, "serve", "--device", "sim", "--profile", "belt-8",
                        "--method", "AS", "--osc-port", "0")  # fmt: skip
    assert code == 2 and "method AS cannot render on this layout" in err


def test_serve_json_that_cannot_be_written_names_the_file(capsys, tmp_path, monkeypatch):
    """A full disk at the end said 'tactile serve: error: No space left on device', naming no
    file; the counters printed above it stand."""
    import errno

    from tactile_core.cli import _serve

    def full(path, data):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(_serve, "write_json_atomic", full)
    out = []
    json_path = tmp_path / "c.json"
    code, err = run_cli(capsys, "serve", "--device", "sim", "--osc-port", "0", "--seconds", "0.1",
                        "--status-s", "0", "--json", json_path, stdout=out)  # fmt: skip
    assert code == 1 and f"cannot write --json {tmp_path / 'c.json'}: No space left" in err
    assert "served " in out[0]
