"""Where lenslab's cache folder cannot be made (a read-only home, a cluster worker's container, ``XDG_CACHE_HOME``
naming a file), a command rebuilds its tables with colour-science as its documentation says, and says nothing of
it: colour-science's import of matplotlib printed two lines of matplotlib's own ("mkdir -p failed for path ...",
"Matplotlib created a temporary cache directory ...") on every such command."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np


def test_a_command_without_a_cache_folder_prints_no_line_of_matplotlib(tmp_path):
    import cv2
    import OpenImageIO as oiio

    codes = np.zeros((16, 32, 3), np.uint8)
    codes[:, :16] = (30, 50, 200)  # BGR for OpenCV
    cv2.imwrite(str(tmp_path / "p.png"), codes)
    (tmp_path / "not-a-folder").write_text("a file where the cache folder would be\n")
    env = {k: v for k, v in os.environ.items() if k not in ("MPLCONFIGDIR", "LENSLAB_CACHE_DIR")}
    env["XDG_CACHE_HOME"] = env["XDG_CONFIG_HOME"] = str(tmp_path / "not-a-folder")
    done = subprocess.run([sys.executable, "-m", "lenslab", "convert", str(tmp_path / "p.png"), "-o",
                           str(tmp_path / "p.exr"), "-q"], capture_output=True, text=True, env=env)
    assert (done.returncode, done.stderr) == (0, "")
    # and the tables built in memory decode the codes by IEC 61966-2-1's curve, transcribed here in float64
    v = np.array([200, 50, 30]) / 255.0
    want = np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)
    got = oiio.ImageBuf(str(tmp_path / "p.exr")).get_pixels(oiio.FLOAT)
    np.testing.assert_allclose(got[:, :16], np.broadcast_to(want, (16, 16, 3)), rtol=2 ** -11)  # half's precision
