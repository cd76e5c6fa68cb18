"""The correction exported as a lookup table for firmware (the tuner's File menu, CSV or a C header
of 256 entries): each raw byte maps to the level the stream itself would send for it, master
intensity and the motors' inverse response included, and the header says which steps it holds."""

import numpy as np

from tactile_core.device.profile import load_profile
from tactile_core.files import export
from tactile_core.rendering.correction import correct, quantize


def test_the_correction_table_is_what_the_stream_sends():
    # It held the correction alone: at mu 0.3, gamma 0.7 and master intensity 0.5 a full raw
    # byte is 0.3 + 0.7 * 0.5 = 0.65, level round(0.65 * 22) = 14 (the table said 22).
    lut = export.correction_lut(0.3, 0.7, 23, gain=0.5)
    assert lut[255] == 14 and lut[0] == 0
    raw = np.arange(256) / 255
    assert np.array_equal(lut, quantize(correct(raw, 0.3, 0.7, gain=0.5), 23))
    palm = load_profile(None)
    felt = export.correction_lut(0.3, 0.7, 23, drive_for=palm.drive_for)
    assert np.array_equal(felt, quantize(palm.drive_for(correct(raw, 0.3, 0.7)), 23))
    header = export.lut_c_header(0.3, 0.7, gain=0.5, drive_for=palm.drive_for)
    assert "Then master intensity 0.5, then the motors' inverse response" in header
