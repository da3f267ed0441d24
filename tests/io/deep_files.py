"""Writing deep EXR test files with the OpenEXR binding: the header of a deep scanline or tiled part."""

from __future__ import annotations


def deep_header(compression, tiles: tuple[int, int] | None = None) -> dict:
    """A deep part's header: ``compression`` (an OpenEXR compression constant), deep scanlines, or deep tiles
    of ``tiles`` (x size, y size)."""
    import OpenEXR

    header = {"compression": compression, "type": OpenEXR.deepscanline}
    if tiles is not None:
        header["type"] = OpenEXR.deeptile
        header["tiles"] = OpenEXR.TileDescription()
        header["tiles"].xSize, header["tiles"].ySize = tiles
    return header
