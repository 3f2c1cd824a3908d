"""Rendering: the rasteriser, cameras and the third-person views, the seeded scenery."""
