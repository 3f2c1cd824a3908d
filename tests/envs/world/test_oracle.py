"""The oracle's spatial grid: the pairs it hands out hold every pair within reach, and what is
computed on them is what every pair gives (a brute force over all pairs, written here as the
reference), for worlds small enough for all pairs and large enough for the grid; and the
pairs a caller gives in its place (the pursuit's worlds, each its own)."""

import numpy as np
import pytest

from animat.envs.world.oracle import ALL_PAIRS, Obstacles, OracleParams, pairs_within, perceived
from animat.envs.world.percepts import AvoidParams, Tank, collision_danger


def _scene(rng, fish: int, side: float, obstacles: int):
    half = side / 2
    points = np.column_stack([rng.uniform(-half, half, (fish, 2)), rng.uniform(-0.6, 0, fish)])
    headings = rng.normal(size=(fish, 3)) * [1, 1, 0.2]
    headings /= np.linalg.norm(headings, axis=1, keepdims=True)
    pillars = Obstacles(rng.uniform(-half, half, (obstacles, 2)),
                        rng.uniform(0.12, 0.25, obstacles), rng.uniform(-0.4, 0.1, obstacles))
    return points, headings, pillars


@pytest.mark.parametrize("count", [30, 900])  # all pairs (30 x 30 < 4096), and the grid
def test_the_pairs_hold_every_pair_within_reach_sorted(count):
    rng = np.random.default_rng(count)
    queries, points = rng.uniform(-20, 20, (count, 3)), rng.uniform(-20, 20, (count + 7, 3))
    assert (count * (count + 7) <= ALL_PAIRS) == (count == 30)
    q, p = pairs_within(queries, points, 1.5)
    flat = np.linalg.norm(queries[:, None, :2] - points[None, :, :2], axis=-1)
    wanted = set(zip(*np.nonzero(flat < 1.5)))
    got = list(zip(q, p))
    assert wanted <= set(got) and len(set(got)) == len(got)  # each pair once
    assert got == sorted(got)
    if count > 30:  # the grid: only the cells next to the query's
        assert len(got) < 0.05 * count * (count + 7) and flat[q, p].max() < 1.5 * 2 * np.sqrt(2)


def _dense_perceived(eyes, headings, targets, reach, obstacles, params):
    """The oracle over every pair (the implementation before the grid)."""
    offsets = targets[None] - eyes[:, None]
    distance = np.linalg.norm(offsets, axis=-1)
    cosine = np.einsum("ftk,fk->ft", offsets, headings) / np.maximum(distance, 1e-9)
    in_field = (cosine >= np.cos(np.radians(0.5 * params.field_deg))) | (
        distance < params.lateral_line)
    a, b = eyes[:, None, None, :], targets[None, :, None, :]
    c = obstacles.centres[None, None]
    d = (b - a)[..., :2]
    length2 = np.maximum(np.einsum("ftkj,ftkj->ftk", d, d), 1e-12)
    s = np.clip(np.einsum("ftkj,ftkj->ftk", c - a[..., :2], d) / length2, 0.0, 1.0)
    through = np.linalg.norm(a[..., :2] + s[..., None] * d - c, axis=-1) < obstacles.radii
    low = np.minimum(a[..., 2], b[..., 2]) < obstacles.tops
    return (distance < reach) & in_field & ~np.any(through & low, axis=-1), distance


@pytest.mark.parametrize("fish, side", [(12, 6.0), (200, 27.0)])
def test_perception_on_the_grid_is_perception_over_every_pair(fish, side):
    rng = np.random.default_rng(fish)
    eyes, headings, pillars = _scene(rng, fish, side, fish // 4)
    food = _scene(rng, 3 * fish // 2, side, 0)[0]
    for targets, reach in ((eyes, 1.5), (food, 2.5)):
        seen, distance = perceived(eyes, headings, targets, reach, pillars, OracleParams())
        want, want_distance = _dense_perceived(eyes, headings, targets, reach, pillars,
                                               OracleParams())
        assert np.array_equal(seen, want) and want.sum() > fish // 2
        assert np.array_equal(distance[seen], want_distance[want])  # to the last bit


def _dense_danger(heads, headings, com, obstacles, tank, avoid, bodies):
    """collision_danger over every fish pair and obstacle (the implementation before the
    grid), without exemptions."""
    f = len(heads)
    probes = heads[:, None] + np.linspace(0.0, avoid.look_ahead, 4)[None, :, None] * headings[
        :, None]
    side = lambda h, o: np.where(h[:, 0] * o[:, 1] - h[:, 1] * o[:, 0] > 0, 1.0, -1.0)  # noqa
    turn, pitch = np.zeros(f), np.zeros(f)
    clearance = obstacles.clearance(np.concatenate([probes, bodies], axis=1)).min(axis=1)
    k = np.argmin(clearance, axis=1)
    close = clearance[np.arange(f), k] < avoid.margin
    towards = np.concatenate([obstacles.centres[k], heads[:, 2:]], axis=1) - heads
    turn = np.where(close, -side(headings, towards), turn)
    ahead = probes[:, -1]
    for axis in (0, 1):
        out = np.abs(ahead[:, axis]) > tank.half_size - avoid.margin
        turn = np.where(out & (turn == 0), side(headings, -heads), turn)
    pitch = np.where(probes[:, :, 2].min(axis=1) < tank.seabed_z + avoid.margin, 1.0, pitch)
    pitch = np.where(probes[:, :, 2].max(axis=1) > tank.top_z - avoid.margin, -1.0, pitch)
    offsets = com[None] - com[:, None]
    gap = np.linalg.norm(offsets, axis=-1) + np.eye(f) * 1e9
    crowd = (gap < avoid.fish_distance) & (np.einsum("ijk,ik->ij", offsets, headings) > 0.0)
    j = np.argmin(np.where(crowd, gap, np.inf), axis=1)
    turn = np.where(crowd.any(axis=1) & (turn == 0), -side(headings, offsets[np.arange(f), j]),
                    turn)
    return (turn != 0) | (pitch != 0), turn, pitch


@pytest.mark.parametrize("fish, side", [(12, 3.0), (300, 21.0)])
def test_collision_danger_on_the_grid_is_the_danger_over_every_pair(fish, side):
    rng = np.random.default_rng(fish + 1)
    heads, headings, pillars = _scene(rng, fish, side, fish // 3)
    bodies = heads[:, None] - np.linspace(0, 0.3, 23)[None, :, None] * headings[:, None]
    com = bodies.mean(axis=1)
    tank = Tank(half_size=side / 2)
    got = collision_danger(heads, headings, com, pillars, tank, AvoidParams(), bodies)
    want = _dense_danger(heads, headings, com, pillars, tank, AvoidParams(), bodies)
    assert all(np.array_equal(a, b) for a, b in zip(got, want))
    assert want[0].sum() > fish // 10 and (want[1] != 0).sum() > fish // 10


def test_worlds_laid_over_each_other_perceive_as_alone_given_their_own_pairs():
    """The pursuit's batch: worlds in the same water, each looking only at its own pairs
    (``pairs``), perceive and avoid as each would alone (on the grid)."""
    rng = np.random.default_rng(7)
    worlds, fish, side = 4, 12, 3.0
    scenes = [_scene(rng, fish, side, 0) for _ in range(worlds)]
    heads, headings = (np.concatenate([scene[k] for scene in scenes]) for k in (0, 1))
    world_of = np.repeat(np.arange(worlds), fish)
    pairs = np.nonzero(world_of[:, None] == world_of[None, :])  # sorted, one world each
    none, tank, avoid = Obstacles.none(), Tank(half_size=side), AvoidParams()
    seen, distance = perceived(heads, headings, heads, 1.5, none, OracleParams(), pairs)
    danger = collision_danger(heads, headings, heads, none, tank, avoid, pairs=pairs)
    assert not seen[world_of[:, None] != world_of[None, :]].any()
    for w, (points, directions, _) in enumerate(scenes):
        rows = slice(w * fish, (w + 1) * fish)
        alone, alone_distance = perceived(points, directions, points, 1.5, none,
                                          OracleParams())
        assert np.array_equal(seen[rows, rows], alone) and alone.sum() > fish // 2
        assert np.array_equal(distance[rows, rows][alone], alone_distance[alone])
        alone_danger = collision_danger(points, directions, points, none, tank, avoid)
        assert all(np.array_equal(a[rows], b) for a, b in zip(danger, alone_danger))
    alone_crowds = [collision_danger(s[0], s[1], s[0], none, tank, avoid)[1] for s in scenes]
    assert sum(int((t != 0).sum()) for t in alone_crowds) > worlds  # some turn from a fish
    mixed = collision_danger(heads, headings, heads, none, tank, avoid)[1]  # without pairs
    assert not np.array_equal(mixed, danger[1])  # the other worlds' fish would count
