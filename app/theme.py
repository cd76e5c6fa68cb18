"""Colours: the system's palette, light or dark, and what the plots take from it.

The plots follow the application palette (the desktop's, or ``--theme light|dark``): their
background is the palette's base colour, their axes and text its text colour, so a dark desktop
gets dark plots instead of white glare. :data:`TACTOR_COLORS` is a qualitative palette of 30
colours that stay distinct from one another and from both backgrounds (no greys, no near-white,
no near-black), so each of the up to 30 tactors of a trace has its own hue; the time cursor is
drawn in the palette's text colour, dashed, which no curve has.
"""

from __future__ import annotations

from PySide6 import QtGui, QtWidgets

# 30 colours chosen greedily for the largest smallest distance in CIELAB (Glasbey's method),
# from sRGB candidates (steps of 6) of lightness L* 40-70 and chroma 35-75, so that each reads on a
# white and on a near-black background and none is a grey; the first is a blue, the rest in order
# of choice, so any first n are as distinct as n can be. Smallest distance among all 30: dE 25;
# among the first 10: dE 43.
TACTOR_COLORS = (
    "#2478b4", "#de9c00", "#f6367e", "#00c078", "#d27efc", "#904e36", "#5a6c00", "#1ebac0",
    "#8a487e", "#fc6c3c", "#005ad2", "#0c6c48", "#ea90a2", "#78ba2a", "#c0a266", "#b40c90",
    "#b49ce4", "#ba1830", "#fc7ecc", "#8ab46c", "#007e18", "#8a6000", "#b4ae30", "#ea906c",
    "#7e48ae", "#a24200", "#b44260", "#5496fc", "#30b4e4", "#fc6c72",
)  # fmt: skip


def plot_colors(palette: QtGui.QPalette | None = None) -> dict:
    """Background, foreground (axes, text, cursor) and a faint shade for the plots."""
    palette = palette or QtWidgets.QApplication.palette()
    base = palette.color(QtGui.QPalette.ColorRole.Base)
    text = palette.color(QtGui.QPalette.ColorRole.Text)
    shade = QtGui.QColor(text)
    shade.setAlpha(28)
    return {"background": base, "foreground": text, "shade": shade}


def apply_theme(app: QtWidgets.QApplication, theme: str) -> None:
    """Fusion with a light or dark palette (``--theme``); "system" leaves the desktop's."""
    if theme == "system":
        return
    app.setStyle("Fusion")
    palette = QtGui.QPalette()
    role = QtGui.QPalette.ColorRole
    if theme == "dark":
        colors = {
            role.Window: "#2b2b2b", role.WindowText: "#e6e6e6", role.Base: "#1e1e1e",
            role.AlternateBase: "#2f2f2f", role.Text: "#e6e6e6", role.Button: "#353535",
            role.ButtonText: "#e6e6e6", role.Highlight: "#3d7bd9", role.HighlightedText: "#ffffff",
            role.ToolTipBase: "#353535", role.ToolTipText: "#e6e6e6",
            role.PlaceholderText: "#8a8a8a", role.BrightText: "#ff6b6b", role.Link: "#6fa8ff",
        }  # fmt: skip
    else:
        colors = {
            role.Window: "#efefef", role.WindowText: "#1a1a1a", role.Base: "#ffffff",
            role.AlternateBase: "#f5f5f5", role.Text: "#1a1a1a", role.Button: "#e6e6e6",
            role.ButtonText: "#1a1a1a", role.Highlight: "#2f6fd0", role.HighlightedText: "#ffffff",
            role.ToolTipBase: "#ffffdc", role.ToolTipText: "#1a1a1a",
            role.PlaceholderText: "#7a7a7a", role.BrightText: "#c0392b", role.Link: "#1f5fbf",
        }  # fmt: skip
    for r, color in colors.items():
        palette.setColor(r, QtGui.QColor(color))
    disabled = QtGui.QColor("#7a7a7a" if theme == "dark" else "#9a9a9a")
    for r in (role.WindowText, role.Text, role.ButtonText):
        palette.setColor(QtGui.QPalette.ColorGroup.Disabled, r, disabled)
    app.setPalette(palette)
