"""Plot views: the live heatmap, the activation curves, the correction curve.

Each view builds its plot items once and updates them in place (``setImage``/``setData``) on
every refresh; images have fixed levels (0, 1) and row-major axis order, so nothing flickers or
re-estimates its range. Colours follow the application palette (light or dark, see
:mod:`tactile_tuner.theme`), and each activated tactor has one of 30 distinct colours, the same
on the heatmap's cell frame and on its activation curve.
"""

from ._common import PALETTE, cell_colors, cell_label, set_title
from .correction import CorrectionView
from .curves import CurvesView
from .heatmap import HeatmapView

__all__ = [
    "PALETTE",
    "CorrectionView",
    "CurvesView",
    "HeatmapView",
    "cell_colors",
    "cell_label",
    "set_title",
]
