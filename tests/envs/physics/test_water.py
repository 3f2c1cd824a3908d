"""The water as the kernels see it: ``Water.as_args`` packs every field into its named slot, and
the slot constants the kernels index by (``water[SURFACE_Z]``) agree with that packing."""

import re
from dataclasses import fields
from pathlib import Path

import numpy as np

from animat.envs.physics import system
from animat.envs.physics.system import SPLIT_FIELDS, WATER_SIZE, WATER_SLOTS, Water

# Every field a different number, so that a slot read from the wrong index shows.
DISTINCT = Water(fluid_coefficient=1.0, air_coefficient=2.0, friction_coefficient=3.0,
                 air_friction_coefficient=4.0, reaction="paper", density=6.0, gravity=7.0,
                 surface_z=8.0, current=(9.0, 10.0, 11.0), air_pressure=12.0,
                 model="reactive", added_mass=14.0 / 7.0)
EXPECTED = {"fluid_coefficient": 1.0, "air_coefficient": 2.0, "friction_coefficient": 3.0,
            "air_friction_coefficient": 4.0, "crossflow": 0.0, "density": 6.0, "gravity": 7.0,
            "surface_z": 8.0, "current_x": 9.0, "current_y": 10.0, "current_z": 11.0,
            "air_pressure": 12.0, "reactive": 1.0, "added_mass": 2.0}


def test_water_packing_round_trips_every_field_to_its_slot_constant():
    """Each slot's constant (its name in capitals) reads back the field it was packed from; the
    constants are exactly the slots' indices, one each, and every Water field has its slots."""
    args = DISTINCT.as_args()
    assert args.dtype == np.float64 and args.shape == (WATER_SIZE,) == (len(WATER_SLOTS),)
    assert set(WATER_SLOTS) == set(EXPECTED)
    for index, name in enumerate(WATER_SLOTS):
        constant = getattr(system, name.upper())
        assert isinstance(constant, int) and constant == index, name
        assert args[constant] == EXPECTED[name], name
    assert sorted(getattr(system, name.upper()) for name in WATER_SLOTS) == list(range(WATER_SIZE))
    packed = {f.name for f in fields(Water)} - set(SPLIT_FIELDS)
    assert packed | {slot for slots in SPLIT_FIELDS.values() for slot in slots} == set(EXPECTED)
    assert Water().as_args()[system.CROSSFLOW] == 1.0  # the default law: cross-flow
    assert Water().as_args()[system.SURFACE_Z] == np.inf  # no surface
    assert Water(model="resistive").as_args()[system.REACTIVE] == 0.0


def test_water_kernels_read_no_bare_slot_number():
    """The compiled terms index the water by the named constants only (no ``water[5]``, no
    ``water[:6]``), so the packing's order lives in one place."""
    bare = re.compile(r"water\[\s*[-\d:]")
    physics = Path(system.__file__).parent
    for path in sorted(physics.glob("*.py")):
        hits = [line for line in path.read_text().splitlines() if bare.search(line)]
        assert not hits, f"{path.name}: {hits}"


# The slots' order the compiled kernels were built with. Numba's on-disk cache (cache=True)
# keys a kernel on its own file only, so a reorder of Water's fields changes the slot constants
# without recompiling the kernels that read them as literals: they would read the wrong slots.
PINNED_SLOTS = ("fluid_coefficient", "air_coefficient", "friction_coefficient",
                "air_friction_coefficient", "crossflow", "density", "gravity", "surface_z",
                "current_x", "current_y", "current_z", "air_pressure", "reactive", "added_mass")


def test_water_slot_order_is_pinned():
    """A change of Water's fields or their order must be made here on purpose, with the
    compiled caches cleared."""
    assert WATER_SLOTS == PINNED_SLOTS, (
        f"the water's slots are now {WATER_SLOTS}: Numba's cached kernels still read the old "
        "order; clear them (find envs -name __pycache__ -exec rm -rf {} +), then update "
        "PINNED_SLOTS in tests/envs/physics/test_water.py")
