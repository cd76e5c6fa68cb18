"""The participant's window: the instructions and the response prompt, nothing else."""

from __future__ import annotations

from PySide6 import QtCore, QtGui, QtWidgets


class ParticipantWindow(QtWidgets.QWidget):
    """What the participant sees: the instructions and the response prompt, nothing else."""

    closed = QtCore.Signal()

    def __init__(self, parent=None):
        super().__init__(parent, QtCore.Qt.WindowType.Window)
        self.setWindowTitle("tactile-tuner - participant")
        self.setObjectName("participant_window")
        layout = QtWidgets.QVBoxLayout(self)
        layout.setContentsMargins(60, 60, 60, 60)
        big = self.font()
        big.setPointSize(big.pointSize() + 12)
        self.prompt = QtWidgets.QLabel("")
        self.prompt.setObjectName("experiment_prompt")
        self.prompt.setWordWrap(True)
        self.prompt.setFont(big)
        self.prompt.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
        self.keys_label = QtWidgets.QLabel("")
        self.keys_label.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
        self.rating_edit = QtWidgets.QLineEdit()
        self.rating_edit.setObjectName("rating")
        self.rating_edit.setFont(big)
        self.rating_edit.setMaximumWidth(220)
        self.rating_edit.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
        self.rating_error = QtWidgets.QLabel("")
        self.rating_error.setObjectName("rating_error")
        self.rating_error.setStyleSheet("color: #c0392b;")
        self.rating_error.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
        self.feedback = QtWidgets.QLabel("")
        self.feedback.setObjectName("experiment_feedback")
        self.feedback.setFont(big)
        self.feedback.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
        self.countdown = QtWidgets.QLabel("")
        self.countdown.setObjectName("experiment_countdown")
        marker = self.font()  # "interval 1", "interval 2": read from across the room
        marker.setPointSize(big.pointSize() + 8)
        marker.setBold(True)
        self.countdown.setFont(marker)
        self.countdown.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
        layout.addStretch(2)
        layout.addWidget(self.prompt)
        layout.addWidget(self.keys_label)
        row = QtWidgets.QHBoxLayout()
        row.addStretch(1)
        row.addWidget(self.rating_edit)
        row.addStretch(1)
        layout.addLayout(row)
        layout.addWidget(self.rating_error)
        layout.addWidget(self.feedback)
        layout.addWidget(self.countdown)
        layout.addStretch(3)
        self.rating_edit.setVisible(False)

    def show_on(self, screen_index: int | None) -> None:
        """Full screen on screen ``screen_index``, or an ordinary window for None."""
        screens = QtGui.QGuiApplication.screens()
        if screen_index is not None and 0 <= screen_index < len(screens):
            self.setScreen(screens[screen_index])
            self.setGeometry(screens[screen_index].geometry())
            self.showFullScreen()
        else:
            self.resize(900, 600)
            self.showNormal()
        self.raise_()
        self.activateWindow()

    def closeEvent(self, event) -> None:  # Qt override
        self.closed.emit()
        super().closeEvent(event)
