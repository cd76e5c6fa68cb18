"""Frame files: frames rendered (``tactile render``) and frames a stream sent (``--record``),
to CSV or NPZ."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .._shared.outfile import atomic_file, check_output
from ..device.frame_log import FrameLog
from ..rendering.geometry import ArraySpec


class Recorder:
    """A streamer tap that keeps every frame written and saves them on :meth:`save`.

    Frames are kept in memory, ``9 + channels`` bytes each (39 bytes for the palm array: about
    42 MB per hour at 300 Hz), and written at the end, so recording adds no file I/O to the
    output thread.

    Parameters
    ----------
    array : ArraySpec
        The array, for the channel order and the column names.
    """

    def __init__(self, array: ArraySpec):
        self.array = array
        self.log = FrameLog(array.size)

    def __call__(self, time_s: float, seq: int, levels: bytes) -> None:
        """Tap interface: record one frame (channel-ordered levels)."""
        self.log.append(time_s, seq, levels)

    def __len__(self) -> int:
        return len(self.log)

    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``time`` (s from the first frame), ``seq`` and ``levels`` ``(n, rows, cols)`` uint8."""
        time_s, seq, channel = self.log.arrays()
        if len(time_s):
            time_s = time_s - time_s[0]
        cells = np.zeros_like(channel)
        cells[:, self.array.channel_index] = channel
        return time_s, seq, cells.reshape(len(seq), *self.array.layout.frame_shape)

    def save(self, path) -> Path:
        """Write ``.csv`` (``time,seq,r0c0,...``) or ``.npz`` (``time``, ``seq``, ``levels``)."""
        path = check_output(path, (".csv", ".npz"), "record file")
        time_s, seq, levels = self.arrays()
        size = self.array.size
        if path.suffix.lower() == ".npz":
            with atomic_file(path, binary=True) as f:
                np.savez(f, time=time_s, seq=seq, levels=levels)
        else:
            names = ["time", "seq", *(self.array.layout.cell_name(i) for i in range(size))]
            with atomic_file(path) as f:
                f.write(",".join(names) + "\n")
                flat = levels.reshape(len(seq), size)
                for t, s, row in zip(time_s.tolist(), seq.tolist(), flat.tolist()):
                    f.write(f"{t:.6f},{s}," + ",".join(map(str, row)) + "\n")
        return path


def write_frames(path, time_s, frames, names) -> None:
    """Write rendered frames: ``.npz`` (arrays ``time`` and ``frames`` as given) or CSV
    (``time`` then one column per tactor, headed by ``names``), atomically.

    Parameters
    ----------
    path : pathlib.Path
        A checked ``.csv`` or ``.npz`` path (:func:`~tactile_core._shared.outfile.check_output`).
    time_s : ndarray of float64, shape (n,)
        Each frame's time, in seconds.
    frames : ndarray of float64, shape (n, ...)
        The frames; the CSV has one column per entry of a frame, in ``names``' order.
    names : sequence of str
        The column names of the tactors (actuators).

    Raises
    ------
    OSError
        When the file cannot be written (nothing is left behind).
    """
    if path.suffix.lower() == ".npz":
        with atomic_file(path, binary=True) as f:
            np.savez(f, time=time_s, frames=frames)
    else:
        table = np.column_stack([time_s, frames.reshape(len(time_s), -1)])
        with atomic_file(path) as f:
            np.savetxt(f, table, delimiter=",", header=",".join(["time", *names]),
                       comments="", fmt="%.10g")  # fmt: skip
