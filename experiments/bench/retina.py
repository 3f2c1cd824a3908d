"""Retina benchmark: both eyes (8 cameras) over the paper's scene, frame-sets per second.

``python -m animat.experiments.bench.retina``: 10 fishes in textured skins (their nodes jittered by
a few
mm), 15 food particles, 5 rocks and 12 plants over a sand seabed, seen by the two eyes of the
first fish; frame-sets (all 8
cameras) per wall second on one core, beside the third-person 480x360 view of the same scene
as a reference measured in the same rounds, and the paper's 1995 figure (about 4 frames per
second for this scene, without vision).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from animat.envs.bodies.fish import fish_body
from animat.envs.render.camera import Camera, Scene, fish_skin, look_at, posed
from animat.envs.render.scenery import SceneryParams, furnish, scatter
from animat.envs.vision.retina import RetinaParams, eye_positions, gaze_rotation, render_eyes


def paper_scene(seed: int = 0) -> Scene:
    """10 fishes in textured skins, 15 food particles, 5 rocks and 12 plants within a 3 m
    square (:mod:`animat.envs.render.scenery`), over a sand seabed 1 m down."""
    rng, body = np.random.default_rng(seed), fish_body()
    scene = furnish(Scene(seabed_z=-1.0), scatter(rng, -1.0, SceneryParams(
        rock_height=0.8, plant_height=0.9)))
    for k in range(10):
        yaw = rng.uniform(-np.pi, np.pi)
        x = posed(body, [*rng.uniform(-1.5, 1.5, 2), rng.uniform(-.3, .3)], yaw)
        x += rng.normal(0.0, 0.004, x.shape)
        if k == 0:
            x = body.rest_positions.copy()
        scene.add(body, x, fish_skin(body, (250, 140, 60) if k else (200, 60, 50)))
    return scene


def eyes_once(scene: Scene, params: RetinaParams) -> None:
    body, x, _ = scene.bodies[0]
    frame = np.eye(3)
    rotation = gaze_rotation(frame, 0.0, 0.0)
    render_eyes(scene, eye_positions(frame, x[0], body.length, params),
                np.stack([rotation, rotation]), params)


def third_person_once(scene: Scene) -> None:
    eye = np.array([-1.0, -2.0, 1.0])
    Camera(480, 360, 432.0, eye, look_at(eye, np.zeros(3))).render(scene)


def rate(fn, seconds: float) -> float:
    fn()
    count, start = 0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        fn()
        count += 1
    return count / (time.perf_counter() - start)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=6.0)
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args(argv)
    scene, params = paper_scene(), RetinaParams()
    eyes, view = [], []
    for _ in range(args.rounds):
        eyes.append(rate(lambda: eyes_once(scene, params), args.seconds / args.rounds / 2))
        view.append(rate(lambda: third_person_once(scene), args.seconds / args.rounds / 2))
    eyes_rate, view_rate = float(np.median(eyes)), float(np.median(view))
    triangles = len(scene.prepare().triangles)
    print(f"scene: 10 fishes, 15 food particles, 5 rocks, 12 plants ({triangles} triangles, "
          "shadows included)")
    print(f"both retinas (8 cameras of 64x64): {eyes_rate:8.1f} frame-sets/s "
          f"({8 * eyes_rate:.0f} camera images/s)")
    print(f"third-person 480x360 view:         {view_rate:8.1f} frames/s")
    print(f"ratio retina frame-sets / third-person frames: {eyes_rate / view_rate:.2f}")
    print("the paper (1995, SGI): about 4 frames/s for this scene, without vision")


if __name__ == "__main__":
    main()
