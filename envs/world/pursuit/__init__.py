"""The vision-guided pursuit in the living world, ``Animat/FishPursuit-v0``: the env
(:mod:`.env`: an observer with eyes, a prey and other fish that live by the world's minds),
its native vector env (:mod:`.vector`), both thin shells (:mod:`.shell`) over one batched core
of worlds (:mod:`.worlds`; where they start: :mod:`.start`, the other fish's minds:
:mod:`.others`), its
senses (:mod:`.senses`: the sensors, the retina among them, read a view of the observer) and the
paper's active-vision policy that pursues by its eyes alone (:mod:`.policy`); an episode's
metrics are in :mod:`.summary`.

Part of the world room: may import the world and every room below it.
"""
