"""``tactile bench``: what rendering costs, and what speed buys in accuracy.

Timings are the minimum over repeated runs (the least disturbed by other processes) of
``time.perf_counter`` around many calls; they are reported, never asserted in tests.

Inside, one module per part: ``_common`` (scenes, timer, :class:`Table`), ``_batch`` and
``_live`` (the rendering cost), ``_layouts`` (on actuators anywhere), ``_accuracy`` (speed
against accuracy), ``_device`` (the link into the emulator), ``_audio`` (the audio callback's
cost per block), ``_methods``, ``_motor_drive`` (motor-aware drive, felt and its cost),
``_staircase``, ``_tuning`` and ``_validation`` (the tuning
against other observers, QUEST+), ``_trade`` (the speed/accuracy trade in felt terms and the
recommended setting per device; its model in ``_trade_model``, devices in ``_trade_target``,
the rule in ``_trade_advice``);
:func:`run` picks the parts.
"""

from __future__ import annotations

from importlib.metadata import entry_points

# ``_name as _name``: helpers of the module before the split, still importable from here.
from ._accuracy import accuracy_table
from ._audio import audio_table, waveform_table
from ._batch import batch_table, dense_area_sampling, naive_area_sampling, ratio_table
from ._common import FILTERS, GAMMA, MU, RATES_HZ, SCENES, Table, best_time
from ._device import EmulatorProcess, device_tables
from ._felt_readout import FeltReadout, felt_readout
from ._layouts import layouts_table
from ._link import link_table
from ._live import live_table
from ._methods import methods_table, winners_table
from ._motor_drive import (
    BOUND_LAG_MM,
    BOUND_ONSET_MS,
    BOUND_RIPPLE,
    FeltEffect,
    felt_effect,
    motor_drive_cost_table,
    motor_drive_rows,
    motor_drive_table,
)
from ._staircase import fit_table, staircase_table
from ._trade import LEVELS, MOTORS_MS, trade_run, trade_settings, trade_tables
from ._trade_advice import CANDIDATE_RATES_HZ, Advice, Candidate, Tolerance, advise, recommend
from ._trade_model import PAPER, Link, Runs, Setting, felt_runs
from ._trade_target import FAMILIES, Family, Target
from ._tuning import TUNING_OBSERVERS, TUNING_PLANS, tuning_table
from ._validation import quest_table, validation_table

__all__ = [
    "BOUND_LAG_MM",
    "BOUND_ONSET_MS",
    "BOUND_RIPPLE",
    "CANDIDATE_RATES_HZ",
    "FAMILIES",
    "FILTERS",
    "GAMMA",
    "LEVELS",
    "MOTORS_MS",
    "MU",
    "PAPER",
    "RATES_HZ",
    "SCENES",
    "TUNING_OBSERVERS",
    "TUNING_PLANS",
    "Advice",
    "Candidate",
    "EmulatorProcess",
    "Family",
    "FeltEffect",
    "FeltReadout",
    "Link",
    "Runs",
    "Setting",
    "Table",
    "Target",
    "Tolerance",
    "accuracy_table",
    "advise",
    "audio_table",
    "batch_table",
    "best_time",
    "dense_area_sampling",
    "device_tables",
    "felt_effect",
    "felt_readout",
    "felt_runs",
    "fit_table",
    "layouts_table",
    "link_table",
    "live_table",
    "methods_table",
    "motor_drive_cost_table",
    "motor_drive_rows",
    "motor_drive_table",
    "naive_area_sampling",
    "quest_table",
    "ratio_table",
    "recommend",
    "run",
    "staircase_table",
    "trade_run",
    "trade_settings",
    "trade_tables",
    "tuning_table",
    "validation_table",
    "waveform_table",
    "winners_table",
]


def run(part: str = "core", quick: bool = False, out=print, profile=None) -> list[Table]:
    """Run the benchmark tables of ``part`` ("core", "methods", "motor", "trade", "device",
    "link", "experiments", "tuning", "gui" or "all"), printed as Markdown; ``profile`` (a
    device profile's name or path) is the device of the trade part (default: the palm array,
    and the recommendations for each actuator family)."""
    tables = []

    def show(table: Table) -> None:
        out(table.markdown())
        out("")
        tables.append(table)

    if part in ("core", "all"):
        sizes = (2000, 20_000) if quick else (2000, 100_000)
        show(batch_table(sizes))
        show(ratio_table(repeat=10 if quick else 40))
        show(live_table())
        show(layouts_table())
        show(accuracy_table(quick=quick))
    if part in ("methods", "all"):
        from ..rendering.methods import method_names
        from ..rendering.motor import PALM_MOTOR
        from ._methods import VARIANTS, _ranges

        samples = 501 if quick else 2001
        ranges = _ranges(samples, [*method_names(), *VARIANTS], PALM_MOTOR)
        show(methods_table(samples=samples, ranges=ranges))
        show(winners_table(samples=samples, ranges=ranges))
    if part in ("motor", "all"):
        show(motor_drive_table())
        show(motor_drive_cost_table())
    if part in ("trade", "all"):
        trade_run(profile, quick=quick, show=show)
    if part in ("device", "all"):
        for table in device_tables(seconds=3.0 if quick else 10.0):
            show(table)
        show(audio_table(blocks=1000 if quick else 4000))
        show(waveform_table(blocks=1000 if quick else 4000))
    if part in ("link", "all"):
        show(link_table(seconds=2.0 if quick else 5.0))
    if part in ("experiments", "all"):
        show(staircase_table(tracks=300 if quick else 2000))
        show(fit_table(tracks=40 if quick else 300))
    if part in ("tuning", "all"):
        show(tuning_table(runs=20 if quick else 200))
        show(validation_table(runs=20 if quick else 200))
        show(quest_table(runs=20 if quick else 200))
    if part in ("gui", "all"):
        # The GUI's benchmark lives with the GUI (tactile_tuner), registered under the entry
        # point group "tactile.bench": the core never imports Qt or the GUI package.
        hooks = [ep for ep in entry_points(group="tactile.bench") if ep.name == "gui"]
        if not hooks:
            out("(GUI benchmark skipped: the tuner is not installed)")
        for hook in hooks:
            try:
                run_gui = hook.load()
            except ImportError as exc:
                out(f"(GUI benchmark skipped: {exc})")
                continue
            tables += run_gui(quick=quick, out=out)
    return tables
