"""A PQ or HLG file (a PNG with a cICP chunk, a HEIC with nclx) decodes to linear light without holding its
image many times over: colour-science's curves work in float64 and make several temporaries of their input's
size, so the codes go through them a band of rows at a time, and the peak of a read stays within a few times
the float32 image it returns (before: 19 times it, 1.9 GB for a 4096 x 2048 16-bit PNG).

Measured with tracemalloc (NumPy reports its buffers to it): a budget of bytes, not of time. The bound, 4
times the float32 image: the image itself, its 16-bit codes (half of it), the file's bytes while OpenCV
decodes them (about half of it for noise) and the bands' temporaries, with room to spare. Values: colour-science
in float64 on the codes (ST 2084 over 203 cd/m², BT.2408's reference white; BT.2100 HLG at L_W = 1000 cd/m²;
its BT.2020 -> BT.709 matrix), float32 rounding apart (relative 1e-6).
"""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

colour = pytest.importorskip("colour")
cv2 = pytest.importorskip("cv2")

import lenslab.io as lio  # noqa: E402
from lenslab.io.colour.png_cicp import with_cicp  # noqa: E402

H, W = 512, 768
TO_709 = colour.matrix_RGB_to_RGB(colour.RGB_COLOURSPACES["ITU-R BT.2020"], colour.RGB_COLOURSPACES["ITU-R BT.709"])


@pytest.mark.parametrize("transfer", [16, 18], ids=["pq", "hlg"])
def test_a_pq_or_hlg_png_is_read_within_a_few_times_its_image(tmp_path, transfer):
    codes = np.random.default_rng(5).integers(0, 65536, (H, W, 3), dtype=np.uint16)
    ok, buf = cv2.imencode(".png", codes[..., ::-1], [cv2.IMWRITE_PNG_COMPRESSION, 1])
    path = tmp_path / "hdr.png"
    path.write_bytes(with_cicp(buf.tobytes(), (9, transfer, 0, 1)))
    lio.read(path)  # (the curves' caches and modules loaded outside the measure)
    tracemalloc.start()
    try:
        img, meta = lio.read(path)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak <= 4 * img.nbytes, peak / img.nbytes
    e = codes / 65535.0
    light = colour.models.eotf_ST2084(e) if transfer == 16 else colour.models.eotf_BT2100_HLG(e, L_B=0, L_W=1000)
    np.testing.assert_allclose(img, (light / 203.0) @ TO_709.T, rtol=1e-6, atol=1e-9)
    assert meta["display_encoded"] is False
