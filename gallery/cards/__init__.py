"""The cards of the gallery page, one function each; a card's text is its function's docstring.

Every card function takes the :class:`~gallery.build.Page` it draws on and its record(s), writes its
images through the page and returns the card's HTML.
"""

from gallery.cards.files import files
from gallery.cards.hdri import hdri
from gallery.cards.lens import lens_comparisons, lens_views
from gallery.cards.panorama import panorama
from gallery.cards.tone import tone_curves, tone_strip
from gallery.cards.validation import validation

__all__ = ["files", "hdri", "lens_comparisons", "lens_views", "panorama", "tone_curves", "tone_strip", "validation"]
