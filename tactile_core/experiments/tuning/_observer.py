"""The model of the module notes, and a simulated observer who answers by it.

A participant feels one tactor driven at ``d`` with magnitude ``((d - TH) / (1 - TH))^K`` above
the threshold ``TH`` and adds tactors by energy; :class:`SimulatedObserver` answers the
procedure's two-interval trials so, with noise, and :func:`simulate_tuning` runs the whole
procedure against it.
"""

from __future__ import annotations

import math
import random
from dataclasses import dataclass, field

import numpy as np

from ..._shared import validate as _validate
from ...rendering.correction import Dither, quantize
from ...rendering.percept import felt_magnitude
from ...rendering.trace import render_frames
from .._correction_record import MU_MAX
from ..results import Session
from ._procedure import CorrectionTuning


def felt_total(drive, threshold: float, exponent: float) -> float:
    """Felt magnitude of a whole frame: the tactors added by energy, ``sqrt(sum m_i^2)``.

    Parameters
    ----------
    drive : array_like of float, any shape (e.g. (rows, cols))
        Each tactor's drive, a fraction of full drive in [0, 1].
    threshold : float
        ``TH``, drive fraction.
    exponent : float
        ``K``.

    Returns
    -------
    float
        ``sqrt(sum m_i^2)`` with each ``m_i`` from
        :func:`~tactile_core.rendering.percept.felt_magnitude` (1: one tactor at full drive).
    """
    m = felt_magnitude(drive, threshold, exponent)
    return float(np.sqrt(np.sum(m * m)))


def interval_drive(scene, profile) -> np.ndarray:
    """What the array's motors get over one interval: the mean drive per tactor.

    The scene is rendered at its frame rate for its duration, calibrated, and quantised (or
    dithered, if the scene dithers) to the profile's levels, exactly as the streamer sends it;
    a motor, far slower than the 300 Hz frames, feels the mean.

    Parameters
    ----------
    scene : Scene or None
        None (or a paused scene) is silence.
    profile : DeviceProfile

    Returns
    -------
    ndarray of float64, shape (rows, cols)
        Mean level / (levels - 1), in [0, 1].
    """
    grid = profile.layout
    if scene is None or not scene.active:
        return np.zeros(grid.shape)
    n = max(1, round(scene.duration_s * scene.rate_hz))
    _, frames = render_frames(
        scene.trace(), scene.method, sampling=scene.sampling(), mu=scene.mu, gamma=scene.gamma,
        grid=grid, n_frames=n, gain=scene.gain,
    )  # fmt: skip
    flat = frames.reshape(n, grid.size)
    if scene.felt_domain:
        flat = profile.drive_for(flat)
    flat = profile.calibrate(flat)
    if scene.dither:
        levels = Dither(grid.size, profile.levels).frames(flat)
    else:
        levels = quantize(flat, profile.levels)
    return (levels.mean(axis=0) / (profile.levels - 1)).reshape(grid.shape)


@dataclass
class SimulatedObserver:
    """The simulated participant of the contract: a power law above a threshold, energy
    summation, noisy answers; and, to test the procedure against participants it was not built
    for, departures from that model.

    On each trial the threshold varies around ``threshold`` (normal, ``threshold_sd``); each
    interval's felt magnitude (:func:`felt_total` of :func:`interval_drive`) is perturbed in log
    units by ``weber`` (normal), and the stronger interval is chosen (an interval felt as nothing
    loses; two of them are a guess). With probability ``lapse`` the answer is a coin toss.

    The departures (all off by default, which is the contract's participant): ``tactor_sd``
    gives each tactor its own threshold, drawn once per observer around ``threshold``;
    ``summation`` is the exponent ``p`` of the power sum ``M = (sum m_i^p)^(1/p)`` (2: energy,
    1: linear); ``masking`` raises a tactor's threshold by that much drive while one of its four
    neighbours is driven above its own threshold.

    Parameters
    ----------
    threshold : float
        ``TH`` in [0, 0.95].
    exponent : float
        ``K`` in [0.1, 10].
    seed : int
    threshold_sd : float
        Trial-to-trial spread of the threshold (drive units): the detection slope.
    weber : float
        Spread of felt magnitude in log units: the discrimination slope.
    lapse : float
        Probability of a random answer, in [0, 0.5].
    profile : DeviceProfile, optional
        The array the stimuli play on (the palm array by default).
    tactor_sd : float
        Spread of the tactors' own thresholds around ``threshold`` (drive units, 0 to 0.3).
    summation : float
        Exponent ``p`` of the power sum over tactors, 0.5 to 10 (2: energy).
    masking : float
        Threshold raise while a neighbour is felt, drive units (0 to 0.5).
    """

    threshold: float = 0.25
    exponent: float = 1.0
    seed: int = 0
    threshold_sd: float = 0.02
    weber: float = 0.15
    lapse: float = 0.03
    profile: object = None
    tactor_sd: float = 0.0
    summation: float = 2.0
    masking: float = 0.0
    _cache: dict = field(default_factory=dict, repr=False)

    def __post_init__(self):
        from ...device.profile import default_profile

        self.threshold = _validate.in_range("threshold", self.threshold, 0.0, MU_MAX)
        self.exponent = _validate.in_range("exponent", self.exponent, 0.1, 10.0)
        self.threshold_sd = _validate.in_range("threshold_sd", self.threshold_sd, 0.0, 0.5)
        self.weber = _validate.in_range("weber", self.weber, 0.0, 5.0)
        self.lapse = _validate.in_range("lapse", self.lapse, 0.0, 0.5)
        self.tactor_sd = _validate.in_range("tactor_sd", self.tactor_sd, 0.0, 0.3)
        self.summation = _validate.in_range("summation", self.summation, 0.5, 10.0)
        self.masking = _validate.in_range("masking", self.masking, 0.0, 0.5)
        self.rng = random.Random(self.seed)
        if self.profile is None:
            self.profile = default_profile()
        shape = self.profile.layout.frame_shape
        offsets = np.zeros(shape)
        if self.tactor_sd > 0.0:
            offsets = np.random.default_rng([self.seed, 20]).normal(0.0, self.tactor_sd, shape)
        self.thresholds = np.clip(self.threshold + offsets, 0.0, MU_MAX)
        """Each tactor's own threshold, ``(rows, cols)``."""

    @property
    def contract(self) -> bool:
        """True for the contract's participant (no departure from the model)."""
        return self.tactor_sd == 0.0 and self.summation == 2.0 and self.masking == 0.0

    def felt(self, drive, shift: float = 0.0) -> float:
        """Felt magnitude of a frame without noise: each tactor above its threshold (shifted by
        ``shift``, raised by masking), summed by the power ``summation``.

        Parameters
        ----------
        drive : array_like of float, shape (rows, cols)
        shift : float
            This trial's shift of every threshold, drive units.
        """
        d = np.asarray(drive, dtype=np.float64)
        th = np.clip(self.thresholds + shift, 0.0, 0.999)
        if self.masking > 0.0:
            on = d > th
            near = np.zeros_like(on)
            near[1:, :] |= on[:-1, :]
            near[:-1, :] |= on[1:, :]
            near[:, 1:] |= on[:, :-1]
            near[:, :-1] |= on[:, 1:]
            th = np.clip(th + self.masking * near, 0.0, 0.999)
        x = np.clip((d - th) / (1.0 - th), 0.0, None)
        m = np.where(d > th, x**self.exponent, 0.0)
        p = self.summation
        return float(np.sum(m**p) ** (1.0 / p))

    @property
    def mu(self) -> float:
        """The right threshold for this observer, ``TH``."""
        return self.threshold

    @property
    def gamma(self) -> float:
        """The right gamma for this observer, ``1 / (2K)``."""
        return 1.0 / (2.0 * self.exponent)

    def drive(self, scene) -> np.ndarray:
        """:func:`interval_drive` of ``scene``, remembered (threshold stimuli repeat)."""
        if scene is None:
            return np.zeros(self.profile.layout.frame_shape)
        hit = self._cache.get(scene)
        if hit is None:
            hit = self._cache[scene] = interval_drive(scene, self.profile)
            if len(self._cache) > 4096:
                self._cache.clear()
        return hit

    def respond(self, trial):
        """The answer to ``trial``: ``"continue"`` to instructions, ``"1"`` or ``"2"`` to a
        two-interval trial."""
        if trial.kind == "continue":
            return "continue"
        if trial.kind != "interval":
            raise ValueError(f"the simulated observer answers interval trials, not {trial.kind!r}")
        rng = self.rng
        if rng.random() < self.lapse:
            return rng.choice(("1", "2"))
        felt = []
        if self.contract:
            th = min(max(rng.gauss(self.threshold, self.threshold_sd), 0.0), 0.999)
        else:
            shift = rng.gauss(0.0, self.threshold_sd)
        for scene in trial.intervals:
            if self.contract:
                m = felt_total(self.drive(scene), th, self.exponent)
            else:
                m = self.felt(self.drive(scene), shift)
            felt.append(math.log(m) + rng.gauss(0.0, self.weber) if m > 0.0 else -math.inf)
        if felt[0] == felt[1]:
            return rng.choice(("1", "2"))
        return "1" if felt[0] > felt[1] else "2"

    def run(self, runner) -> None:
        """Answer every remaining trial of ``runner``."""
        while not runner.finished:
            runner.answer(self.respond(runner.current), rt_s=1.0)


def simulate_tuning(threshold: float, exponent: float, seed: int = 0, plan=None, **observer):
    """Run the procedure against a :class:`SimulatedObserver` in memory.

    Parameters
    ----------
    threshold, exponent : float
        The observer's ``TH`` and ``K``.
    seed : int
        Seeds the observer and the procedure.
    plan : TuningPlan, optional
    **observer
        Further :class:`SimulatedObserver` parameters (``threshold_sd``, ``weber``, ``lapse``,
        ``profile``, and the departures ``tactor_sd``, ``summation``, ``masking``).

    Returns
    -------
    TuningResult
    """
    seed = _validate.integer("seed", seed, 0, 2**31 - 1)
    sim = SimulatedObserver(threshold, exponent, seed=seed, **observer)
    session = Session(participant="simulated", seed=seed)
    runner = CorrectionTuning(session, plan, write=False, profile=sim.profile)
    sim.run(runner)
    return runner.result()
