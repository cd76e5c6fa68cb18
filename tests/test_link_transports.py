"""A serial link on each transport pyserial offers (a pseudo-terminal, ``spy://``,
``socket://``, ``rfc2217://``, ``loop://``): it reads everything that has arrived, and a write
that completed is never a write timeout, whatever the host did meanwhile."""

import itertools
import os
import select
import socket
import threading
import time
import tty

import pytest
import serial
from serial import rfc2217

from tactile_core.device.link import SerialLink
from tactile_core.device.wire import (
    ClockReply,
    MessageReader,
    Status,
    encode_clock_reply,
    encode_frame,
    encode_status,
)

# What an array answers: a clock reply (23 bytes on the wire) and a status (16).
REPLIES = encode_clock_reply(ClockReply(7, 1_000, 1_100, 0, 0, 3)) + encode_status(
    Status(8, 12_345, 0, 0)
)


class Device:
    """The far end of a link: ``send`` bytes to the host, ``received()`` what the host wrote,
    and ``arrived(link)``, how many bytes wait unread at the host's end."""

    def __init__(self, url, send, received, arrived, close=lambda: None):
        self.url, self.send, self.received, self.arrived, self.close = (
            url, send, received, arrived, close,
        )  # fmt: skip


def pty_device(prefix=""):
    master, slave = os.openpty()
    tty.setraw(master)
    tty.setraw(slave)
    got = bytearray()

    def received():
        while select.select([master], [], [], 0)[0]:
            got.extend(os.read(master, 65536))
        return bytes(got)

    def close():
        for fd in (master, slave):
            os.close(fd)

    return Device(prefix + os.ttyname(slave), lambda data: os.write(master, data), received,
                  lambda link: link._port.in_waiting, close)  # fmt: skip


class TcpDevice:
    """A TCP server with one client; with ``telnet``, pyserial's own RFC 2217 server side
    (``PortManager``) in between, as a network serial bridge has."""

    def __init__(self, telnet=False):
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.conn = None
        self.manager = None
        self.telnet = telnet
        self.got = bytearray()
        self.stop = False
        self.connected = threading.Event()
        self.thread = threading.Thread(target=self.run, daemon=True)
        self.thread.start()

    def run(self):
        conn, _ = self.listener.accept()
        self.conn = conn
        if self.telnet:
            self.manager = rfc2217.PortManager(serial.serial_for_url("loop://"), self)
        self.connected.set()
        while not self.stop:
            if not select.select([conn], [], [], 0.02)[0]:
                continue
            data = conn.recv(65536)
            if not data:
                return
            chunks = self.manager.filter(data) if self.telnet else [data]
            self.got.extend(b"".join(chunks))

    def write(self, data):  # PortManager's connection: its negotiation goes straight out
        self.conn.sendall(data)

    def send(self, data):
        assert self.connected.wait(10)
        if self.telnet:
            data = b"".join(self.manager.escape(data))
        self.conn.sendall(data)

    def close(self):
        self.stop = True
        self.thread.join(5)
        if self.conn is not None:
            self.conn.close()
        self.listener.close()


def socket_device(telnet=False):
    device = TcpDevice(telnet)
    port = device.listener.getsockname()[1]

    def waiting_in_socket(link):
        try:
            return len(link._port._socket.recv(65536, socket.MSG_PEEK | socket.MSG_DONTWAIT))
        except BlockingIOError:
            return 0

    if telnet:  # the RFC 2217 client reads the socket in a thread of its own, into a queue
        return Device(f"rfc2217://127.0.0.1:{port}", device.send, lambda: bytes(device.got),
                      lambda link: link._port.in_waiting, device.close)  # fmt: skip
    return Device(f"socket://127.0.0.1:{port}", device.send, lambda: bytes(device.got),
                  waiting_in_socket, device.close)  # fmt: skip


def loop_device():
    # loop:// hands back what the host writes: the "device" sends by the host's own write
    holder = {}

    def send(data):
        holder["link"].write(data)

    device = Device("loop://", send, lambda: b"", lambda link: link._port.in_waiting)
    device.holder = holder
    return device


TRANSPORTS = {
    "pty": pty_device,
    "spy": lambda: pty_device("spy://"),
    "socket": socket_device,
    "rfc2217": lambda: socket_device(telnet=True),
    "loop": loop_device,
}


OLD_THREAD_CALLS = pytest.mark.filterwarnings("ignore:set(Daemon|Name):DeprecationWarning")
"""pyserial's RFC 2217 client calls the threads' setDaemon and setName."""


@pytest.fixture(params=[pytest.param(kind, marks=OLD_THREAD_CALLS) for kind in sorted(TRANSPORTS)])
def device(request):
    made = TRANSPORTS[request.param]()  # (spy:// writes its hex dump to standard error)
    made.kind = request.param
    yield made
    made.close()


def open_link(device):
    link = SerialLink(device.url)
    if hasattr(device, "holder"):
        device.holder["link"] = link
    return link


def wait_for(predicate, timeout_s=10.0):
    end = time.monotonic() + timeout_s
    while not predicate():
        assert time.monotonic() < end, "timed out"
        time.sleep(0.002)


def test_one_read_takes_every_byte_that_has_arrived(device):
    # SerialLink.read read in_waiting bytes: pyserial's socket:// says 1 when anything is there
    # and an rfc2217:// read without waiting gives one byte, so a 23-byte clock reply took 23
    # frame polls (74 ms at 300 Hz) and the host's reading of the array's clock went ~30 ms off.
    link = open_link(device)
    try:
        device.send(REPLIES)
        wait_for(lambda: device.arrived(link) >= len(REPLIES))
        got = link.read()
        assert got == REPLIES
        messages = MessageReader(accept=(ClockReply, Status)).feed(got)
        assert [type(m) for m in messages] == [ClockReply, Status]
        assert link.read() == b""  # and nothing twice
    finally:
        link.close()


def test_a_host_paused_during_a_write_is_no_write_timeout(device, monkeypatch):
    # pyserial 3.5 reads the monotonic clock as a write starts and again once the bytes are
    # out: a host paused between the two (SIGSTOP, a VM pause) turned a completed write into
    # "write timeout ... not taking data". Here the host pauses 0.3 s, more than the 0.2 s
    # write timeout, between any two readings of that clock; the device reads all along.
    ticks = itertools.count()
    monkeypatch.setattr(serial.serialutil.Timeout, "TIME", staticmethod(lambda: next(ticks) * 0.3))
    link = open_link(device)
    frames = [encode_frame(seq, [seq % 23] * 30) for seq in range(20)]
    try:
        for frame in frames:
            link.write(frame)
            if device.kind != "loop":
                device.received()  # a device reading as it should
        if device.kind == "loop":
            wait_for(lambda: device.arrived(link) >= sum(map(len, frames)))
            assert link.read() == b"".join(frames)
        else:
            wait_for(lambda: len(device.received()) >= sum(map(len, frames)))
            assert device.received() == b"".join(frames)
    finally:
        link.close()


def test_a_device_that_takes_nothing_is_still_a_write_timeout():
    master, slave = os.openpty()  # nobody reads the master: the buffer fills, then stays full
    tty.setraw(master)
    tty.setraw(slave)
    link = SerialLink(os.ttyname(slave), write_timeout_s=0.05)
    frame = encode_frame(0, [5] * 30)
    try:
        with pytest.raises(Exception, match=r"write timeout: .* is not taking data"):
            for _ in range(100_000):
                link.write(frame)
    finally:
        link.close()
        os.close(master)
        os.close(slave)
