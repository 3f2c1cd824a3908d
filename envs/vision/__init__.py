"""Vision: the foveated retinas (:mod:`.retina`, a sensor), perception (:mod:`.perception`:
colour histograms, backprojection, optical flow, range) and the active-vision primitives
(:mod:`.active_vision`: saccades, vergence, stabilisation).

May import motor, render, physics, bodies and checks; not core or world (a sensor reads
whatever offers eyes, see :class:`~animat.envs.vision.retina.Sighted`).
"""
