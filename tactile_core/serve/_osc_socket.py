"""Where the OSC server listens: the host as written, the socket, what to show of a sender.

:func:`listen_host` takes an IPv6 address in brackets (``[::1]``, as the server's first line
``osc://[::1]:9100`` writes it) as well as bare; :func:`check_listen` says whether the server
could listen on an address now (``tactile serve`` asks before it opens the device, so that a
port in use is said first).
"""

from __future__ import annotations

import ipaddress
import socket

__all__ = ["check_listen", "listen_host", "where"]


def _printable(text: str) -> str:
    """``text`` with what a terminal would act on escaped: a sender's address or method name
    reaches the summary printed on the operator's terminal, and ESC [ 2 J in one cleared it."""
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


def listen_host(host: str) -> str:
    """``host`` as the socket takes it: an IPv6 address in brackets (``[::1]``, as URLs and the
    server's own first line write it) without them; ``ValueError`` for an empty host or
    brackets around something that is not an IPv6 address."""
    text = host.strip() if isinstance(host, str) else ""
    if text.startswith("[") and text.endswith("]"):
        inner = text[1:-1]
        try:
            ipaddress.IPv6Address(inner.split("%")[0])
        except ValueError:
            raise ValueError(
                f"host must be an address or a host name (127.0.0.1, ::1 or [::1], 0.0.0.0, a "
                f"name); brackets hold an IPv6 address, got {host!r}"
            ) from None
        return inner
    if not text:
        raise ValueError(
            f"host must be an address or a host name (127.0.0.1, ::1 or [::1], 0.0.0.0, a "
            f"name), got {host!r}"
        )
    return text


def where(host: str, port: int) -> str:
    """``host:port``, an IPv6 address in brackets (``[::1]:9100``)."""
    return f"[{host}]:{port}" if ":" in host else f"{host}:{port}"


def check_listen(host: str, port: int) -> None:
    """Raise ``OSError`` (saying where and why: the address in use, not an address of this
    machine) if the server could not listen on ``host``, ``port`` now; bind and close a socket
    there, so that a command can say so before it opens anything else."""
    _open_socket(listen_host(host), port).close()


def _open_socket(host: str, port: int) -> socket.socket:
    at = where(host, port)
    try:
        family, _, _, _, addr = socket.getaddrinfo(host, port, type=socket.SOCK_DGRAM)[0]
    except (socket.gaierror, UnicodeError) as exc:
        raise OSError(f"cannot listen on {at}: {exc}") from None
    sock = socket.socket(family, socket.SOCK_DGRAM)
    try:
        sock.bind(addr)
    except OSError as exc:
        sock.close()
        error = OSError(f"cannot listen on {at}: {exc.strerror or exc}")
        error.errno = exc.errno  # (an address in use: EADDRINUSE, for a hint)
        raise error from None
    return sock


def _loopback(host: str) -> bool:
    """True for an address of this machine only: 127/8, ::1, and IPv4 loopback written as
    IPv6 (``::ffff:127.0.0.1``, which Python before 3.13 does not call loopback)."""
    ip = ipaddress.ip_address(host.split("%")[0])
    mapped = getattr(ip, "ipv4_mapped", None)
    return (mapped or ip).is_loopback
