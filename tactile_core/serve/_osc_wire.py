"""OSC 1.0 packets read from a UDP datagram: messages, bundles, argument types.

The server reads packets with this small reader rather than python-osc's, for three reasons
that matter on a port anyone on the machine can send to: it finds string ends with
``bytes.find`` (python-osc walks strings a byte at a time in Python, so a 60 KB datagram of junk
costs milliseconds), it turns every defect into one :class:`Malformed` (python-osc lets a bad
UTF-8 string escape as ``UnicodeDecodeError`` and only logs an unknown type tag, then reads the
arguments after it out of step), and it bounds what one datagram may cost before the work is
done: at most :data:`MAX_DATAGRAM_BYTES` bytes, :data:`MAX_ARGUMENTS` type tags a message
(checked on the tag string's length, before a tag is read: 65,000 ``[`` tags took 41 ms to read
one by one), bundles :data:`MAX_DEPTH` deep, and the messages it is asked for. It reads what
python-osc writes (``tests/test_serve_osc.py`` checks both ways); :func:`encode_message`
writes the server's replies.

Bundle time tags are read and ignored: a bundle's messages apply when it arrives.
"""

from __future__ import annotations

import struct

__all__ = [
    "MAX_ARGUMENTS",
    "MAX_DATAGRAM_BYTES",
    "MAX_DEPTH",
    "Malformed",
    "encode_message",
    "read_packet",
]

MAX_DEPTH = 8
"""Deepest nesting of bundles read."""
MAX_DATAGRAM_BYTES = 16_384
"""Longest datagram read, in bytes: 256 point messages with their ids in one bundle, or a
``/tactile/shape`` of the most points it may have at full precision, fit with room to spare."""
MAX_ARGUMENTS = 16
"""Most type tags a message may have (an array's brackets count): the address space takes at
most three arguments."""

_BUNDLE = b"#bundle\x00"
_FIXED = {
    "i": (4, ">i"),
    "f": (4, ">f"),
    "d": (8, ">d"),
    "h": (8, ">q"),
    "t": (8, ">Q"),
    "c": (4, ">i"),
    "r": (4, ">I"),
    "m": (4, ">I"),
}
_CONSTANT = {"T": True, "F": False, "N": None, "I": float("inf")}


class Malformed(ValueError):
    """The datagram is not an OSC packet (the message says where it went wrong)."""


def _string(data: bytes, start: int) -> tuple[str, int]:
    end = data.find(b"\x00", start)
    if end < 0:
        raise Malformed(f"string at byte {start} has no terminating NUL")
    try:
        text = data[start:end].decode("utf-8")
    except UnicodeDecodeError:
        raise Malformed(f"string at byte {start} is not UTF-8") from None
    return text, (end + 4) & ~3


def _message(data: bytes) -> tuple[str, list]:
    address, index = _string(data, 0)
    if not address.startswith("/"):
        raise Malformed(f"address must start with '/', got {address[:40]!r}")
    if index >= len(data):
        return address, []  # no type tag string: no arguments (OSC 1.0 allows it)
    end = data.find(b"\x00", index)
    if end - index > MAX_ARGUMENTS + 1:  # (no NUL at all: _string says so)
        raise Malformed(f"more than {MAX_ARGUMENTS} type tags (arguments) in one message")
    tags, index = _string(data, index)
    if not tags.startswith(","):
        raise Malformed("the type tag string must start with ','")
    args: list = []
    stack = [args]
    for tag in tags[1:]:
        if tag in _FIXED:
            size, fmt = _FIXED[tag]
            if index + size > len(data):
                raise Malformed(f"argument '{tag}' runs past the end of the datagram")
            value = struct.unpack_from(fmt, data, index)[0]
            index += size
        elif tag in ("s", "S"):
            value, index = _string(data, index)
        elif tag == "b":
            if index + 4 > len(data):
                raise Malformed("blob size runs past the end of the datagram")
            size = struct.unpack_from(">i", data, index)[0]
            if size < 0 or index + 4 + size > len(data):
                raise Malformed("blob runs past the end of the datagram")
            value = data[index + 4 : index + 4 + size]
            index += 4 + ((size + 3) & ~3)
        elif tag in _CONSTANT:
            value = _CONSTANT[tag]
        elif tag == "[":
            inner: list = []
            stack[-1].append(inner)
            stack.append(inner)
            continue
        elif tag == "]" and len(stack) > 1:
            stack.pop()
            continue
        else:
            raise Malformed(f"unknown type tag {tag!r}")
        stack[-1].append(value)
    if len(stack) != 1:
        raise Malformed("an array in the type tags is not closed")
    if index > len(data):
        raise Malformed("the arguments run past the end of the datagram")
    return address, args


def read_packet(data: bytes, max_messages: int) -> tuple[list[tuple[str, list]], int]:
    r"""The messages of one datagram, in order, and how many more it held beyond
    ``max_messages`` (those are not read): ``([(address, [arguments...]), ...], skipped)``.

    Arguments come out as Python values: ``int`` (i, h, c, r, m, t), ``float`` (f, d, I),
    ``str`` (s, S), ``bytes`` (b), ``True``/``False``/``None`` (T, F, N), lists (arrays).
    A bundle gives its messages (nested bundles included, at most :data:`MAX_DEPTH` deep).
    :class:`Malformed` if the datagram is not an OSC packet.

    >>> read_packet(b"/tactile/off\x00\x00\x00\x00", 10)
    ([('/tactile/off', [])], 0)
    """
    if len(data) > MAX_DATAGRAM_BYTES:
        raise Malformed(f"a datagram of {len(data)} bytes: at most {MAX_DATAGRAM_BYTES} are read")
    out: list = []
    skipped = [0]
    _packet(bytes(data), out, max_messages, 0, skipped)
    return out, skipped[0]


def _padded(raw: bytes) -> bytes:
    raw += b"\x00"
    return raw + b"\x00" * (-len(raw) % 4)


def encode_message(address: str, args: tuple | list = ()) -> bytes:
    r"""One OSC message: ``str`` arguments as ``s``, ``int`` as ``i``, ``float`` as ``f``
    (32-bit, what Max, Pd and TouchDesigner read everywhere).

    >>> encode_message("/tactile/error", ["/tactile/mu", "out of range"])[:16]
    b'/tactile/error\x00\x00'
    """
    tags, body = [","], []
    for value in args:
        if isinstance(value, str):
            tags.append("s")
            body.append(_padded(value.encode("utf-8", "backslashreplace")))
        elif isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ValueError(f"OSC reply argument must be str, int or float, got {value!r}")
        elif isinstance(value, int):
            tags.append("i")
            body.append(struct.pack(">i", value))
        else:
            tags.append("f")
            body.append(struct.pack(">f", value))
    return _padded(address.encode()) + _padded("".join(tags).encode()) + b"".join(body)


def _packet(data: bytes, out: list, limit: int, depth: int, skipped: list) -> None:
    if len(data) % 4:
        raise Malformed(f"an OSC packet is a multiple of 4 bytes long, got {len(data)}")
    if not data.startswith(_BUNDLE):
        if len(out) < limit:
            out.append(_message(data))
        else:
            skipped[0] += 1
        return
    if depth >= MAX_DEPTH:
        raise Malformed(f"bundles nested more than {MAX_DEPTH} deep")
    if len(data) < 16:
        raise Malformed("a bundle needs its 8-byte time tag")
    index = 16
    while index < len(data):
        if index + 4 > len(data):
            raise Malformed("bundle element size runs past the end")
        size = struct.unpack_from(">i", data, index)[0]
        index += 4
        if size <= 0 or index + size > len(data):
            raise Malformed(f"bundle element of {size} bytes does not fit")
        if len(out) < limit:
            _packet(data[index : index + size], out, limit, depth + 1, skipped)
        else:
            skipped[0] += 1  # not read: a nested bundle counts as one
        index += size
