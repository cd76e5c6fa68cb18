"""The OSC server and the LSL outlets beside a stream's output thread, run by commands: in the
stream process, and in this process for a thread stream; the same events either way."""

import queue
import socket
import uuid

import pytest
from pythonosc.udp_client import SimpleUDPClient

from tactile_core.rendering.scene import Scene
from tactile_core.stream import StreamerProcess, StreamServices, open_stream

from .serve_support import wait_for


class Events:
    def __init__(self):
        self.queue = queue.Queue()

    def __call__(self, kind, payload):
        self.queue.put((kind, payload))

    def wait(self, kind, timeout_s=15.0, send=None):
        """The payload of the next event of ``kind`` (others are skipped); ``send()`` between
        looks, for a point that has to be refreshed."""
        while True:
            if send is not None:
                send()
            try:
                got, payload = self.queue.get(timeout=timeout_s if send is None else 0.05)
            except queue.Empty:
                if send is not None:
                    timeout_s -= 0.05
                    if timeout_s > 0:
                        continue
                raise AssertionError(f"no {kind} event") from None
            if got == kind:
                return payload

    def kinds(self):
        out = []
        while not self.queue.empty():
            out.append(self.queue.get()[0])
        return out


def port_free(port):
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    try:
        sock.bind(("127.0.0.1", port))
        return True
    except OSError:
        return False
    finally:
        sock.close()


@pytest.mark.parametrize("process", [True, False])
def test_services_serve_osc_on_the_stream_wherever_it_runs(process):
    stream = open_stream(None, process=process)
    events = Events()
    live = StreamServices(stream, events)
    client = None
    try:
        live.start_osc(Scene(method="AS", mu=0.33, gamma=0.7), port=0)
        host, port = events.wait("osc-started")
        client = SimpleUDPClient(host, port)
        lit = lambda: client.send_message("/tactile/point", [0.5, 0.5])  # noqa: E731
        stats, points = events.wait("osc-stats", send=lit)
        while not points:
            stats, points = events.wait("osc-stats", send=lit)
        assert points[0][:3] == ("", 0.5, 0.5) and stats.last_sender.startswith("127.0.0.1:")
        wait_for(lambda: lit() or stream.last_levels[0, 0] == 22, what="the point on the array")
        # The owner's changes are not echoed; a sender's are.
        live.set_osc_scene(Scene(method="GS", mu=0.5, gamma=0.7))
        client.send_message("/tactile/gamma", 2.0)  # (it may overtake the owner's scene)
        assert events.wait("osc-scene") == {"gamma": 2.0}
        client.send_message("/tactile/method", "RO")
        assert events.wait("osc-scene") == {"method": "RO"}
        live.set_osc_scene(Scene(method="IM"))
        assert "needs a shape" in events.wait("osc-refused")
        live.stop_osc()
        final = events.wait("osc-stopped")
        assert final.points > 0 and final.controls == 2 and port_free(port)
        sid = f"test-{uuid.uuid4().hex}"
        live.open_lsl(source_id=sid)
        assert events.wait("lsl-opened") == {"levels": False, "source_id": sid}
        live.close_lsl()
        events.wait("lsl-closed")
    finally:
        if client is not None:
            client.close()
        live.close()
        stream.stop()
    assert stream.last_levels.sum() == 0


def test_services_commands_may_not_take_the_streams_own_kinds():
    stream = StreamerProcess()
    with pytest.raises(ValueError, match="the stream's own"):
        stream.command("scene", 0, None)


@pytest.mark.parametrize("process", [True, False])
def test_services_a_bad_command_is_an_event_and_the_stream_goes_on(process):
    stream = open_stream(None, process=process)
    events = Events()
    stream.on_event.append(events)
    try:
        stream.command("bogus", 1)
        assert "unknown command 'bogus'" in events.wait("error")
        stream.command("osc-start", {"scene": Scene(), "host": "no such host", "port": 0})
        assert "cannot listen on no such host" in events.wait("osc-failed")
        frames = stream.stats.frames
        wait_for(lambda: stream.stats.frames > frames + 30, what="frames after the bad commands")
    finally:
        stream.stop()
