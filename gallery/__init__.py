"""gallery: builds an HTML page of what lenslab does, from its own renders."""
