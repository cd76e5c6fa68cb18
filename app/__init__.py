"""The tuner: a Qt desktop application over :mod:`tactile_core` (PySide6 + pyqtgraph).

Data flows one way: widgets write to :class:`app.state.TunerState`, which emits ``*_changed``
signals; the views listen and redraw; :class:`app.device.DeviceController` hands each new scene
to the streamer, whose output thread never touches a widget.
"""
