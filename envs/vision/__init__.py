"""Vision: the foveated retinas (a sensor), perception (colour histograms, backprojection, flow,
range) and the active-vision primitives."""
