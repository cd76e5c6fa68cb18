"""Single key presses at the terminal, for the guided procedures (no Enter needed).

At a terminal the key is read in cbreak mode (no line editing, no echo; the key is echoed by
hand) and the terminal is restored whatever happens. Cbreak is set, and keys pressed earlier
(while the intervals played) are dropped, before the prompt appears: a key counts only once the
question has been asked, and none pressed after it is lost. From a pipe or a file, keys are read one
character at a time, so a script may send them one per line as before. Whitespace is skipped
unless asked for (Enter and Space answer a "continue").
"""

from __future__ import annotations

import codecs
import os
import select
import sys

POLL_S = 0.05
"""While waiting for a key, how often the stop request (Ctrl-C) is looked at, s."""


def read_key(prompt: str, *, whitespace: bool = False, stop=None) -> str:
    """Print ``prompt`` on standard error and return the next key pressed, lower-cased.

    Parameters
    ----------
    prompt : str
        What to ask (no newline needed).
    whitespace : bool
        Return Enter and Space (as ``"\\n"`` and ``" "``) instead of skipping them.
    stop : object with ``is_set()``, optional
        Looked at every :data:`POLL_S` while waiting: once set (Ctrl-C's handler sets it),
        ``"q"`` is returned, the key that stops. A read of standard input would go on waiting
        through Ctrl-C, whose handler only sets the request.

    Raises
    ------
    EOFError
        Standard input ended.
    """
    stream = sys.stdin
    if stream.isatty():
        key = _tty_key(stream, whitespace, prompt, stop)
    else:
        sys.stderr.write(prompt)
        sys.stderr.flush()
        key = _stream_key(stream, whitespace, stop)
    sys.stderr.write((key if key.strip() else "") + "\n")
    sys.stderr.flush()
    return key


def _reader(stream, stop):
    """A function returning the next character of ``stream`` ("" at its end, None once
    ``stop`` is set). On a file descriptor it waits with ``select`` and reads bytes itself (the
    text layer's buffer would hide what is waiting); elsewhere (Windows, a stream without one)
    it reads the stream and cannot be stopped while waiting."""
    try:
        fd = stream.fileno()
    except (AttributeError, OSError, ValueError):
        fd = None
    if fd is None or os.name == "nt" or stop is None:
        return lambda: stream.read(1)
    decoder = codecs.getincrementaldecoder("utf-8")(errors="replace")

    def read():
        while not stop.is_set():
            ready, _, _ = select.select([fd], [], [], POLL_S)
            if not ready:
                continue
            data = os.read(fd, 1)
            if not data:
                return ""
            ch = decoder.decode(data)
            if ch:
                return ch
        return None

    return read


def _key(read, whitespace: bool) -> str:
    while True:
        ch = read()
        if ch is None:  # asked to stop
            return "q"
        if ch in ("", "\x04"):  # the end, or Ctrl-D at the terminal (the end, as in a line read)
            raise EOFError("standard input ended")
        if whitespace and ch in "\n\r ":
            return "\n" if ch == "\r" else ch
        if not ch.isspace():
            return ch.lower()


def _stream_key(stream, whitespace: bool, stop=None) -> str:
    return _key(_reader(stream, stop), whitespace)


def _tty_key(stream, whitespace: bool, prompt: str, stop=None) -> str:
    import termios
    import tty

    fd = stream.fileno()
    saved = termios.tcgetattr(fd)
    try:
        tty.setcbreak(fd)
        termios.tcflush(fd, termios.TCIFLUSH)  # keys pressed before the question
        sys.stderr.write(prompt)
        sys.stderr.flush()
        return _key(_reader(stream, stop), whitespace)
    finally:
        termios.tcsetattr(fd, termios.TCSADRAIN, saved)
