"""An unknown part selector's error names every part the user may pick, not the first 8: the Beachball
multipart file of ../shared/data has 10 parts, and its last two ('disparityR' among them) were cut to
'and 2 more' in the error, so the user could not read the names to type. The names expected are OpenEXR's
own reading of the file's headers."""

from __future__ import annotations

import pytest

from lenslab import io as lio


@pytest.mark.parametrize("selector", ["nope", "12"])
def test_the_error_names_every_part(shared_data, selector):
    import OpenEXR

    path = shared_data / "formats" / "openexr-images" / "Beachball" / "multipart.0001.exr"
    with OpenEXR.File(str(path), header_only=True) as f:
        names = [p.header["name"] for p in f.parts]
    assert len(names) == 10  # (the manifest's 10 parts)
    with pytest.raises(lio.FormatError) as caught:
        lio.read(f"{path}:{selector}")
    message = str(caught.value)
    assert "\n" not in message and "more" not in message
    for name in names:
        assert repr(name) in message
