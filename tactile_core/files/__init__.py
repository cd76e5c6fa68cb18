"""Documents the tool reads and writes: presets (a tuned scene) and exports (curves, tables).

Above rendering and the device layer: a preset names a device profile and holds a scene; an
export writes activation curves and the correction's lookup table.
"""

from .presets import Preset, PresetError, builtin_presets, load_preset, save_preset

__all__ = ["Preset", "PresetError", "builtin_presets", "load_preset", "save_preset"]
