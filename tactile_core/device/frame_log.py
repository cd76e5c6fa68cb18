"""Frames kept compactly: a time, a sequence number and the levels, in numpy blocks.

A Python list of ``(float, int, bytes)`` costs about 110 bytes a frame (~120 MB an hour at
300 Hz); a block of ``float64``, ``uint8`` and ``channels`` bytes costs ``9 + channels`` (39 bytes
for the palm array, ~42 MB an hour). With ``capacity`` the log keeps only the latest frames
(whole blocks are dropped from the front), so a process that runs for days stays bounded.
"""

from __future__ import annotations

from collections import deque

import numpy as np

BLOCK = 16_384
"""Frames per block: 640 KB for 30 channels; appending never copies what is kept."""


class FrameLog:
    """An append-only log of frames, optionally bounded to the latest ``capacity``.

    Parameters
    ----------
    channels : int
        Levels per frame (bytes).
    capacity : int, optional
        Keep at least this many of the latest frames and fewer than ``capacity + 2 * BLOCK``; None
        keeps every frame.
    """

    def __init__(self, channels: int, capacity: int | None = None):
        if capacity is not None and capacity < 1:
            raise ValueError(f"a frame log keeps at least one frame, got capacity {capacity}")
        self.channels = int(channels)
        self.capacity = capacity
        self._blocks: deque[tuple[np.ndarray, np.ndarray, np.ndarray]] = deque()
        self._fill = BLOCK  # frames used in the last block (BLOCK: a new block is needed)
        self._total = 0
        self._dropped = 0
        self._latest = None

    def append(self, time_s: float, seq: int, levels: bytes) -> None:
        """Add one frame: its time (s), sequence number (0-255) and ``channels`` levels."""
        if self._fill == BLOCK:
            self._new_block()
        block = self._blocks[-1]
        i = self._fill
        block[0][i] = time_s
        block[1][i] = seq
        block[2][i] = np.frombuffer(levels, dtype=np.uint8)
        self._fill = i + 1
        self._latest = (block, i)  # one assignment: a reader in another thread sees whole frames
        self._total += 1

    def _new_block(self) -> None:
        self._blocks.append(
            (
                np.empty(BLOCK, np.float64),
                np.empty(BLOCK, np.uint8),
                np.empty((BLOCK, self.channels), np.uint8),
            )
        )
        self._fill = 0
        if self.capacity is not None:
            while self.kept - BLOCK >= self.capacity:  # the oldest block is not needed
                self._blocks.popleft()
                self._dropped += BLOCK

    def __len__(self) -> int:
        """Frames ever appended (kept or not)."""
        return self._total

    @property
    def kept(self) -> int:
        """Frames still in the log."""
        return self._total - self._dropped

    @property
    def dropped(self) -> int:
        """Frames dropped from the front to keep within ``capacity``."""
        return self._dropped

    @property
    def nbytes(self) -> int:
        """Memory held by the blocks, in bytes."""
        return len(self._blocks) * BLOCK * (9 + self.channels)

    def last(self) -> bytes | None:
        """The levels of the latest frame, or None before the first."""
        latest = self._latest
        return None if latest is None else latest[0][2][latest[1]].tobytes()

    def last_seq(self) -> int | None:
        """The sequence number of the latest frame, or None before the first."""
        latest = self._latest
        return None if latest is None else int(latest[0][1][latest[1]])

    def arrays(self, start: int = 0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The kept frames from frame number ``start`` on (counted over all frames appended).

        Returns
        -------
        times : ndarray, shape (n,), float64
            The times as appended (s).
        seqs : ndarray, shape (n,), uint8
        levels : ndarray, shape (n, channels), uint8
        """
        latest, dropped = self._latest, self._dropped  # safe while another thread appends
        parts = []
        for block in list(self._blocks):
            if latest is None:
                break
            if block is latest[0]:
                parts.append(tuple(a[: latest[1] + 1] for a in block))
                break
            parts.append(block)
        if parts:
            times, seqs, levels = (np.concatenate(p) for p in zip(*parts))
        else:
            times = np.zeros(0)
            seqs = np.zeros(0, np.uint8)
            levels = np.zeros((0, self.channels), np.uint8)
        skip = max(0, int(start) - dropped)
        return times[skip:], seqs[skip:], levels[skip:]
