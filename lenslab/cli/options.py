"""Option values that several commands parse the same way (standard library only, so --help stays instant)."""

from __future__ import annotations


def parse_exposure(text: str) -> float | str:
    """``--exposure``: a number of stops, or ``"auto"``; anything else is a ToneError that says so."""
    if str(text).strip().lower() == "auto":
        return "auto"
    try:
        return float(text)
    except ValueError:
        from lenslab.errors import ToneError

        raise ToneError(f"--exposure must be a number of stops or 'auto', not {text!r}") from None
