"""The tuner: a Qt desktop application over :mod:`tactile_core` (PySide6 + pyqtgraph).

Data flows one way: widgets write to :class:`app.state.TunerState`, which emits ``*_changed``
signals; the views listen and redraw; :class:`app.device.DeviceController` hands each new scene
to the streamer, whose output thread never touches a widget.

The main window (:mod:`.window`) is a shell: it builds the parts, connects them through the
state's signals and small callbacks, and decides what a run or a blind test hides. Each part
knows the state, the device controller and the core, never another part:

- :mod:`.tune` - the Tune tab: heatmap, activation curves, correction curve; the live display;
  pulses, draw mode and scrubbing on the plots.
- :mod:`.compare` - methods side by side; :mod:`.blind` - blind A/B on the array, the view of
  a :class:`tactile_core.experiments.BlindSession`.
- :mod:`.experiments` - the experimenter's console, the participant's window, guided tuning.
- :mod:`.controls` - the controls dock; :mod:`.device_panel` - the device dock;
  :mod:`.timeline` - the pattern editor's dock (its state a Qt-free model).
- :mod:`.files` - presets, exports, profiles; :mod:`.menus` - the menu bar; :mod:`.keys` - the
  application-wide keys.

What the parts share: :mod:`.views` (plot widgets), :mod:`.widgets` (small widgets),
:mod:`.frames` (a scene's frames as the stream renders them), :mod:`.texts`, :mod:`.dialogs`,
:mod:`.theme`.
"""
