"""The pattern editor: a time line of a pattern's effects on tracks, edited with the mouse and
the keys, a property panel, undo and redo, played and scrubbed through the tuner's stream.

:mod:`.model` holds the editor's state without Qt (the pattern, the selection, the playhead,
the file) and the edits; :mod:`.editor` applies them as undoable commands and plays the
pattern; :mod:`.view` (the time line), :mod:`.panel` (the properties) and :mod:`.dock` are its
views; :mod:`.files` opens, saves, imports and exports.
"""

from .dock import TimelinePanel, install_timeline, show_editor
from .editor import TimelineEditor
from .model import SNAP_S, TimelineModel

__all__ = [
    "SNAP_S",
    "TimelineEditor",
    "TimelineModel",
    "TimelinePanel",
    "install_timeline",
    "show_editor",
]
