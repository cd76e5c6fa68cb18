"""Threshold/gamma correction (paper section 2.6) and quantisation to device levels."""

from __future__ import annotations

import numpy as np

from .._shared import validate as _validate


def check_correction(mu, gamma) -> tuple[float, float]:
    """Validate correction parameters: ``mu`` in [0, 1], ``gamma`` finite and > 0."""
    return _validate.in_range("mu", mu, 0.0, 1.0), _validate.positive("gamma", gamma)


def correct(intensity, mu: float, gamma: float, *, gain: float = 1.0) -> np.ndarray:
    """Threshold/gamma correction: ``(1 - mu) I**gamma + mu`` where ``I > 0``; zero stays zero.

    Parameters
    ----------
    intensity : array_like of float, any shape
        Raw intensities ``I`` in [0, 1].
    mu : float
        Threshold in [0, 1]: the smallest intensity a lit tactor receives.
    gamma : float
        Gamma, finite and > 0. Values below 1 raise low intensities, above 1 lower them.
    gain : float, keyword-only
        Master intensity in [0, 1] (beyond the paper): it scales only the part above the
        threshold, ``mu + gain (1 - mu) I**gamma``, so no lit tactor drops below ``mu``.

    Returns
    -------
    ndarray of float64, same shape
        Corrected intensities in [0, 1] (clipped at 1 against rounding).

    Raises
    ------
    ValueError
        Naming ``mu``, ``gamma`` or ``intensity``.

    Notes
    -----
    The paper applies the correction to the anti-aliased methods (AS, IM); on the bi-level
    methods it is the identity, since ``correct(1) = 1`` and ``correct(0) = 0``. Very small
    intensities with large ``gamma`` underflow to ``I**gamma = 0`` and get exactly ``mu``.

    Examples
    --------
    >>> correct([0.0, 0.25, 1.0], mu=0.33, gamma=0.7).round(4)
    array([0.    , 0.5839, 1.    ])
    """
    mu, gamma = check_correction(mu, gamma)
    gain = _validate.in_range("gain", gain, 0.0, 1.0)
    values = _validate.intensity_array("intensity", intensity)
    with np.errstate(under="ignore"):
        adjusted = np.minimum(mu + gain * (1.0 - mu) * np.power(values, gamma), 1.0)
    return np.where(values > 0.0, adjusted, 0.0)


def correct1(value: float, mu: float, gamma: float, gain: float = 1.0) -> float:
    """Scalar :func:`correct` for the live path; arguments are not checked."""
    if value <= 0.0:
        return 0.0
    return min(mu + gain * (1.0 - mu) * value**gamma, 1.0)


def check_levels(levels) -> int:
    """Validate a number of device levels: an integer from 2 to 256 (one byte on the wire)."""
    return _validate.integer("levels", levels, 2, 256)


def quantize(intensity, levels: int = 23) -> np.ndarray:
    """Device levels of intensities: ``floor(I * (levels - 1) + 0.5)``.

    Parameters
    ----------
    intensity : array_like of float, any shape
        Intensities in [0, 1].
    levels : int
        Number of device levels, 2..256; 23 on the paper's array (0 = off, 22 = full).

    Returns
    -------
    ndarray of uint8, same shape
        Levels ``0 .. levels - 1``. Zero stays zero; an intensity below ``0.5 / (levels - 1)``
        also becomes 0, so a lit tactor can be sent as off unless ``mu`` lifts it.

    Examples
    --------
    >>> quantize([0.0, 0.5, 1.0], levels=23)
    array([ 0, 11, 22], dtype=uint8)
    """
    levels = check_levels(levels)
    values = _validate.intensity_array("intensity", intensity)
    return np.floor(values * (levels - 1) + 0.5).astype(np.uint8)


def quantize1(value: float, levels: int) -> int:
    """Scalar :func:`quantize` for the live path; arguments are not checked."""
    return int(value * (levels - 1) + 0.5)


class Dither:
    """Temporal dithering to device levels: first-order error feedback per channel.

    Each frame, a lit channel's level is its intensity in level units plus the residual the
    previous frames left, rounded; the new residual is what the rounding dropped (always within
    [-0.5, 0.5)). Over frames the levels then average to the intensity, so 23 levels carry
    finer averages: a steady 0.33 is sent as 7, 7, 8, 7, 7, 8, ... (average 7.26 = 0.33 x 22)
    instead of 7 (0.318) every frame. An off channel (intensity 0) is sent as 0 and its
    residual cleared, so dithering never makes an off tactor buzz.

    Parameters
    ----------
    channels : int
        Number of channels.
    levels : int
        Number of device levels, 2..256.
    """

    def __init__(self, channels: int, levels: int):
        self.levels = check_levels(levels)
        self._top = self.levels - 1
        self.residual = [0.0] * channels

    def reset(self) -> None:
        """Forget the residuals (e.g. when the scene changes)."""
        self.residual = [0.0] * len(self.residual)

    def level1(self, channel: int, value: float) -> int:
        """Level of one channel this frame (scalar live path)."""
        if value <= 0.0:
            self.residual[channel] = 0.0
            return 0
        x = value * self._top + self.residual[channel]
        level = min(max(int(x + 0.5), 0), self._top)
        self.residual[channel] = x - level
        return level

    def frames(self, intensities) -> np.ndarray:
        """Dither a sequence of frames, ``(n, ...)`` in [0, 1], to uint8 levels (same shape).

        Continues from (and updates) the current residuals; channels are the flattened
        trailing axes.
        """
        values = _validate.intensity_array("intensity", intensities)
        n = values.shape[0]
        flat = values.reshape(n, -1)
        if flat.shape[1] != len(self.residual):
            raise ValueError(
                f"intensity frames must have {len(self.residual)} channels, got {flat.shape[1]}"
            )
        residual = np.array(self.residual)
        out = np.empty(flat.shape, dtype=np.uint8)
        for k in range(n):
            lit = flat[k] > 0.0
            x = flat[k] * self._top + residual
            level = np.clip(np.floor(x + 0.5), 0, self._top)
            residual = np.where(lit, x - level, 0.0)
            out[k] = np.where(lit, level, 0)
        self.residual = residual.tolist()
        return out.reshape(values.shape)
