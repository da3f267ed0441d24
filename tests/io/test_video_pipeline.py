"""The video pipeline's shortcuts give what the plain steps give: a decoded frame's table lookup is
colour-science's transfer function at every 16-bit code value, and the decode thread hands frames and
errors over in order."""

from __future__ import annotations

from fractions import Fraction
import threading

import numpy as np
import pytest

from lenslab.io.video.prefetch import ahead
from lenslab.io.video import VideoInfo, codes16_to_linear, to_linear


@pytest.mark.parametrize("transfer", [1, 13, 16, 18], ids=["bt1886", "srgb", "pq", "hlg"])
@pytest.mark.parametrize("primaries", [1, 9], ids=["bt709", "bt2020"])
def test_table_lookup_is_the_transfer_function_bit_for_bit(transfer, primaries):
    info = VideoInfo(8, 8, Fraction(24), 1, "h264", "yuv420p", primaries=primaries, transfer=transfer)
    rng = np.random.default_rng(transfer + primaries)
    codes = rng.integers(0, 65536, (31, 17, 3), dtype=np.uint16)
    codes[0, :3] = [[0, 0, 0], [65535, 65535, 65535], [1, 32768, 65534]]
    got = codes16_to_linear(codes, info)
    want = to_linear(codes.astype(np.float64) / 65535.0, info)  # colour-science, value by value
    assert got.dtype == np.float32
    np.testing.assert_array_equal(got, want)


def test_frames_ahead_come_in_order_and_an_error_follows_them():
    def items():
        yield from range(5)
        raise OSError("cut file")

    got = []
    with pytest.raises(OSError, match="cut file"):
        for v in ahead(items(), 2):
            got.append(v)
    assert got == [0, 1, 2, 3, 4]


def test_leaving_early_stops_the_decode_thread():
    closed = threading.Event()

    def items():
        try:
            for i in range(10**9):
                yield i
        finally:
            closed.set()

    gen = ahead(items(), 2)
    assert [next(gen) for _ in range(3)] == [0, 1, 2]
    gen.close()  # returns once the producer has ended (it closes its source on the way out)
    assert closed.is_set()
    assert not any(t.name == "lenslab-decode" and t.is_alive() for t in threading.enumerate())
