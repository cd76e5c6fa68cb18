"""The console's analysis: ``tactile analyze`` on the results folder, in the background."""

from __future__ import annotations

import io
import threading
import time
from pathlib import Path

from PySide6 import QtCore, QtGui, QtWidgets

from tactile_core.experiments.analysis import analyze


class AnalysisWidget(QtWidgets.QGroupBox):
    """Analyses the results folder: the tables in a fixed-width output, the figures in tabs.

    The analysis runs in a thread; its progress and result come back as signals, so the window
    stays responsive. The row of buttons also holds *Save calibrated profile...*, which the
    console enables after a calibration.

    Parameters
    ----------
    folder : callable
        The results folder to analyse (the console's).
    """

    error_raised = QtCore.Signal(str)
    _analysis_done = QtCore.Signal(object, str)
    _analysis_progress = QtCore.Signal(float, str)

    def __init__(self, folder, parent=None):
        super().__init__("Analysis", parent)
        self.folder = folder
        r = QtWidgets.QVBoxLayout(self)
        row = QtWidgets.QHBoxLayout()
        self.analyze_button = QtWidgets.QPushButton("Analyze results folder")
        self.paper_rounding_check = QtWidgets.QCheckBox("paper's rounding of p")
        self.paper_rounding_check.setToolTip(
            "Round each p to three decimals before x 6, as the paper's tables did"
        )
        self.save_profile_button = QtWidgets.QPushButton("Save calibrated profile...")
        self.save_profile_button.setEnabled(False)
        for w in (self.analyze_button, self.save_profile_button):
            row.addWidget(w)
        row.addStretch(1)
        r.addLayout(row)
        r.addWidget(self.paper_rounding_check)
        self.analysis_progress = QtWidgets.QProgressBar()
        self.analysis_progress.setVisible(False)
        r.addWidget(self.analysis_progress)
        self.output = QtWidgets.QPlainTextEdit()
        self.output.setReadOnly(True)
        self.output.setPlaceholderText("analysis output")
        self.output.setLineWrapMode(QtWidgets.QPlainTextEdit.LineWrapMode.NoWrap)
        self.output.setFont(
            QtGui.QFontDatabase.systemFont(QtGui.QFontDatabase.SystemFont.FixedFont)
        )
        self.figures = QtWidgets.QTabWidget()
        self.figures.setObjectName("analysis_figures")
        split = QtWidgets.QSplitter(QtCore.Qt.Orientation.Vertical)
        split.addWidget(self.output)
        split.addWidget(self.figures)
        r.addWidget(split, 1)
        self.analyze_button.clicked.connect(self.run_analysis)
        self._analysis_done.connect(self._on_analysis_done)
        self._analysis_progress.connect(self._on_analysis_progress)
        self._analysis_thread = None
        self._analysis_result = None

    def run_analysis(self, wait: bool = False) -> bool:
        """Run ``tactile analyze`` on the results folder in the background; its tables go to
        the output (fixed-width), its figures to tabs. ``wait`` blocks until it is done (for
        tests and scripts); returns whether it succeeded (True at once when not waiting)."""
        if self._analysis_thread is not None and self._analysis_thread.is_alive():
            return False
        folder = self.folder()
        rounding = self.paper_rounding_check.isChecked()
        self.output.setPlainText(f"analysing {folder} ...")
        self.analysis_progress.setRange(0, 100)
        self.analysis_progress.setValue(0)
        self.analysis_progress.setVisible(True)
        self.analyze_button.setEnabled(False)
        self._analysis_result = None

        def work():
            buffer = io.StringIO()
            try:
                result = analyze(
                    folder,
                    out=lambda s="": buffer.write(f"{s}\n"),
                    paper_rounding=rounding,
                    progress=lambda f, what: self._analysis_progress.emit(f, what),
                )
            except (ValueError, OSError) as exc:
                self._analysis_done.emit(None, str(exc))
                return
            self._analysis_done.emit(result, buffer.getvalue())

        self._analysis_thread = threading.Thread(target=work, name="analyze", daemon=True)
        self._analysis_thread.start()
        if wait:
            deadline = time.monotonic() + 120
            while self._analysis_result is None and time.monotonic() < deadline:
                QtWidgets.QApplication.processEvents(
                    QtCore.QEventLoop.ProcessEventsFlag.AllEvents, 50
                )
            return bool(self._analysis_result)
        return True

    def _on_analysis_progress(self, fraction: float, what: str) -> None:
        self.analysis_progress.setValue(round(fraction * 100))
        self.analysis_progress.setFormat(f"{what} %p%")

    def _on_analysis_done(self, result, text: str) -> None:
        self.analysis_progress.setVisible(False)
        self.analyze_button.setEnabled(True)
        if result is None:
            self.output.setPlainText(text)
            self.error_raised.emit(text)
            self._analysis_result = False
            return
        self.output.setPlainText(text)
        while self.figures.count():
            widget = self.figures.widget(0)
            self.figures.removeTab(0)
            widget.deleteLater()
        for path in result.get("figures", []):
            label = QtWidgets.QLabel()
            label.setPixmap(QtGui.QPixmap(path))
            label.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
            scroll = QtWidgets.QScrollArea()
            scroll.setWidget(label)
            scroll.setWidgetResizable(True)
            self.figures.addTab(scroll, Path(path).stem)
        self._analysis_result = True
