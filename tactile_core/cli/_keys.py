"""Single key presses at the terminal, for the guided procedures (no Enter needed).

At a terminal the key is read in cbreak mode (no line editing, no echo; the key is echoed by
hand) and the terminal is restored whatever happens. Cbreak is set, and keys pressed earlier
(while the intervals played) are dropped, before the prompt appears: a key counts only once the
question has been asked, and none pressed after it is lost. From a pipe or a file, keys are read one
character at a time, so a script may send them one per line as before. Whitespace is skipped
unless asked for (Enter and Space answer a "continue").
"""

from __future__ import annotations

import sys


def read_key(prompt: str, *, whitespace: bool = False) -> str:
    """Print ``prompt`` on standard error and return the next key pressed, lower-cased.

    Parameters
    ----------
    prompt : str
        What to ask (no newline needed).
    whitespace : bool
        Return Enter and Space (as ``"\\n"`` and ``" "``) instead of skipping them.

    Raises
    ------
    EOFError
        Standard input ended.
    """
    stream = sys.stdin
    if stream.isatty():
        key = _tty_key(stream, whitespace, prompt)
    else:
        sys.stderr.write(prompt)
        sys.stderr.flush()
        key = _stream_key(stream, whitespace)
    sys.stderr.write((key if key.strip() else "") + "\n")
    sys.stderr.flush()
    return key


def _stream_key(stream, whitespace: bool) -> str:
    while True:
        ch = stream.read(1)
        if ch == "":
            raise EOFError("standard input ended")
        if whitespace and ch in "\n\r ":
            return "\n" if ch == "\r" else ch
        if not ch.isspace():
            return ch.lower()


def _tty_key(stream, whitespace: bool, prompt: str) -> str:
    import termios
    import tty

    fd = stream.fileno()
    saved = termios.tcgetattr(fd)
    try:
        tty.setcbreak(fd)
        termios.tcflush(fd, termios.TCIFLUSH)  # keys pressed before the question
        sys.stderr.write(prompt)
        sys.stderr.flush()
        while True:
            ch = stream.read(1)
            if ch == "":
                raise EOFError("standard input ended")
            if ch == "\x04":  # Ctrl-D at the terminal: the end, as in a line read
                raise EOFError("standard input ended")
            if whitespace and ch in "\n\r ":
                return "\n" if ch == "\r" else ch
            if not ch.isspace():
                return ch.lower()
    finally:
        termios.tcsetattr(fd, termios.TCSADRAIN, saved)
