"""Words the parts share: rich-text tooltips, why draw mode takes only some methods, and how a
correction value is written."""

from __future__ import annotations

import html

DRAW_HELP = (
    "MM and IM pick one tactor per column (or row) of a stroke of the shape, so they need a "
    "shape: a free point has no stroke. CT and AS depend on the point alone, as the paper "
    "notes for its touchpad."
)


# What the window says when a part is locked (a run or a blind session on).
HIDDEN_BLIND = (
    "Blind A/B in progress: the display is hidden so that it does not give the method away. "
    "Reveal in the Blind A/B tab to see it again."
)
HIDDEN_EXPERIMENT = (
    "An experiment is running: the display is hidden so that it does not give the stimulus away."
)
RUN_FILES = (
    "An experiment run is going on: a preset or a .tact file opened now would change the "
    "stimulus its trials record. Stop the run first."
)
BLIND_FILES = (
    "Blind A/B in progress: presets and curve exports would name the hidden method. Reveal "
    "(or cancel the session) in the Blind A/B tab first."
)
PROFILE_BLOCKED = "The device profile cannot change {}: it is for this array's layout."


def value3(x: float) -> str:
    """A correction value (mu, gamma) as the tuner writes it everywhere (the boxes, the titles,
    the status line, file names), to the 0.001 the gamma slider steps in: three decimals where
    the value needs them, else two (``0.143``, ``0.70``, ``0.33``, ``1.00``, ``50.00``). Below
    0.1 and from a million up (a preset's, another program's, the gamma box stepped down) it
    keeps three significant digits, so that no value in use reads as another (``0.05``,
    ``0.0099``, ``1.23e-05``, ``2.5e+06``)."""
    if x != 0 and not 0.1 <= abs(x) < 1e6:
        return f"{x:.3g}"
    text = f"{x:.3f}"
    return text[:-1] if text.endswith("0") else text


def tip(text: str) -> str:
    """A tooltip that wraps (rich text) instead of one line as wide as the screen.

    Parameters
    ----------
    text : str
        The tooltip's plain text.

    Returns
    -------
    str
        ``text`` marked as rich text (``<qt>...</qt>``), its ``<``, ``>`` and ``&`` escaped: a
        file or device name in a tooltip is shown as written, never read as markup.
    """
    return f"<qt>{html.escape(text, quote=False)}</qt>"


def count(n: int, noun: str) -> str:
    """``"1 path"``, ``"2 paths"``: a count with its noun (a plural in s)."""
    return f"{n} {noun}" + ("" if n == 1 else "s")
