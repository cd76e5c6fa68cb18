"""What the current setting costs in felt terms, for the device box.

One row of ``tactile bench --part trade`` for the scene on the array
(:func:`tactile_core.bench.felt_readout`): felt ripple, centroid lag and onset at the skin at
the scene's frame rate, filter, dithering and motor-aware drive, the profile's levels and motors
and the stream's lead, beside the best of the array. It takes a tenth of a second on the palm
array, so it runs in a thread of its own a moment after the last change, and each result is
kept per setting: going back to a setting shows it at once.
"""

from __future__ import annotations

import threading

from PySide6 import QtCore

from .texts import tip

UNREACHED = (
    "felt: not predicted here (a live source, actuators that are not a grid, or a trace "
    "longer than 20 s)"
)


class FeltCost(QtCore.QObject):
    """Watches the scene, the profile and the lead; emits :attr:`changed` with the read-out.

    Parameters
    ----------
    device : DeviceController
        Its ``state.scene``, ``profile`` and ``lead_ms``.
    delay_ms : int
        Quiet time after a change before computing (a dragged slider computes once).
    """

    changed = QtCore.Signal(str, str)
    """``(text, tooltip)`` of the read-out."""
    _computed = QtCore.Signal(object, object)

    def __init__(self, device, parent=None, delay_ms: int = 300):
        super().__init__(parent)
        self.device = device
        self.enabled = True
        self._cache: dict = {}
        self._busy = False
        self._timer = QtCore.QTimer(self)
        self._timer.setSingleShot(True)
        self._timer.setInterval(delay_ms)
        self._timer.timeout.connect(self._start)
        self._computed.connect(self._on_computed)
        device.state.scene_changed.connect(self.schedule)
        device.profile_changed.connect(self.schedule)
        device.connection_changed.connect(self.schedule)  # a new lead reopens the stream
        self.schedule()

    def key(self) -> tuple:
        """What the read-out depends on (not the epoch, playing or the place on the trace)."""
        s, p = self.device.state.scene, self.device.profile
        return (repr(s.shape), s.source is not None, s.method, s.mu, s.gamma, s.duration_s,
                s.rate_hz, s.filter, s.subsamples, s.dither, s.compensate_motors,
                repr((p.name, p.array, p.motor, p.baud, p.carrier_hz)),
                self.device.lead_ms)  # fmt: skip

    def set_enabled(self, enabled: bool) -> None:
        """Off while the read-out is hidden (a blind test, a run): nothing is computed."""
        self.enabled = enabled
        if enabled:
            self.schedule()

    def schedule(self, *_) -> None:
        """Compute the read-out after :attr:`delay_ms` without another change."""
        if self.enabled:
            self._timer.start()

    def _start(self) -> None:
        key = self.key()
        if key in self._cache:
            self._show(self._cache[key])
            return
        if self._busy:
            return  # the running computation looks again when it ends
        self._busy = True
        args = (key, self.device.state.scene, self.device.profile, self.device.lead_ms)
        threading.Thread(target=self._work, args=args, name="tactile-felt-cost",
                         daemon=True).start()  # fmt: skip

    def _work(self, key, scene, profile, lead_ms) -> None:
        from tactile_core.bench import felt_readout

        try:
            result = felt_readout(scene, profile, lead_ms)
        except ValueError as exc:  # a method refused on these actuators, a bad value
            result = f"felt: not predicted ({exc})"
        try:
            self._computed.emit(key, result)
        except RuntimeError:  # the window closed while this ran: nobody to tell
            pass

    def _on_computed(self, key, result) -> None:
        self._busy = False
        self._cache[key] = result
        if key == self.key():
            self._show(result)
        else:
            self.schedule()

    def _show(self, result) -> None:
        if result is None or isinstance(result, str):
            text = result or UNREACHED
            self.changed.emit(text, tip(text))
            return
        s = result.setting
        self.changed.emit(result.text, tip(
            f"What this setting costs in felt terms: the reference participant (threshold 0.2) "
            f"through the profile's motors ({result.motor_label}, {result.motor_source}), "
            f"{s.rate_hz:.4g} frames a "
            f"second, {s.sampling.label}, {s.levels} levels, "
            f"{'dithered' if s.dither else 'rounded'}, lead {s.lead_ms:g} ms, "
            f"{'motor-aware' if s.compensate else 'plain'} drive. Best: the best of this "
            "setting, with motor-aware drive, and at the fastest rate the link carries. Ripple: "
            "max / min of the felt intensity; lag: the felt centroid's distance from the point; "
            "onset: when a tactor is first felt against when it should be. The whole trade: "
            "tactile bench --part trade (docs: Benchmarks)."
        ))  # fmt: skip
