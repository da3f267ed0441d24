"""An EXR attribute under an Exif number's name (``Exif:FocalLength``...) that holds text is read as a number only
where the text is a decimal or a fraction of at most 64 characters that an IEEE 754 double holds: ``1e999999999`` is
no focal length (Python's ``float`` reads it as infinity), and reading it exactly would build a 10**999999999 integer
(hours of CPU and 400 MB) from 5 KB of header."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from lenslab.exif_tags import checked, exr_tags


@pytest.mark.parametrize("text", ["1e999999", "1e-999999", "-1e999999", "9" * 5000, "1" + "0" * 70,
                                  "1e99999/1", "1/1e99999", "nan", "inf", "0x10", "\x1f999"])
def test_text_no_double_holds_is_no_value(text):
    # (float() is the outside reading: each text is either no decimal Python's float reads, or one it reads as
    # infinity, zero from an exponent beyond a double's range, or a number of more digits than a camera writes)
    assert checked("FocalLength", text) is None
    assert checked("PhotographicSensitivity", text) is None


@pytest.mark.parametrize("text, value", [("6.5", Fraction(13, 2)), ("681/100", Fraction(681, 100)),
                                         (" 24 ", Fraction(24)), ("2.5e1", Fraction(25)), ("1e-3", Fraction(1, 1000))])
def test_a_decimal_text_is_its_exact_value(text, value):
    assert checked("FocalLength", text) == value


def test_an_exr_header_of_huge_exponents_reads_no_number():
    header = {"Exif:FocalLength": "1e999999999", "Exif:FocalLengthIn35mmFilm": "1e-999999999",
              "Exif:SubjectDistance": np.array([1.0] * 3), "Make": "Acme"}
    assert exr_tags(header) == {"Make": "Acme"}
