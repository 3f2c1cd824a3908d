"""Rendering: the rasteriser (:mod:`.raster`), scenes and cameras (:mod:`.camera`), the seeded
scenery (:mod:`.scenery`) and the view beside the pool (:mod:`.seaworld`).

May import physics, bodies and checks.
"""
