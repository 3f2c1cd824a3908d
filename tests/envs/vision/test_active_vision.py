"""The active-vision loop on a static scene: both eyes foveate a red fish (not the yellow one
beside it), verge on it, and range it by triangulation."""

import numpy as np
import pytest

from animat.envs.bodies.fish import fish_body
from animat.envs.render.camera import Scene, posed
from animat.envs.vision.active_vision import correlate, detect, foveate, model_histogram, verge
from animat.envs.vision.retina import RetinaParams, eye_positions, gaze_rotation, render_eye

HEAD = np.eye(3)
LENGTH = 0.30


def _fish(centre, yaw):
    body = fish_body()
    return body, posed(body, centre, yaw)


def _scene(with_target=True, with_decoy=True):
    scene = Scene(seabed_z=-0.5)
    if with_target:
        scene.add(*_fish([0.55, 0.25, 0.06], 1.2), (220, 50, 40))
    if with_decoy:
        scene.add(*_fish([0.7, -0.3, 0.0], -0.4), (230, 210, 40))
    return scene


def _model():
    """The target's model image: seen from elsewhere, what differs from the empty water."""
    eye, rotation = np.array([0.2, 0.4, 0.1]), gaze_rotation(HEAD, -0.6, -0.1)
    seen = render_eye(_scene(with_decoy=False), eye, rotation)[2]
    empty = render_eye(_scene(with_target=False, with_decoy=False), eye, rotation)[2]
    return model_histogram(seen, background=np.all(seen == empty, axis=-1))


@pytest.mark.parametrize("start", [(0.0, 0.0), (-0.3, 0.1)])
def test_both_eyes_foveate_the_red_fish_and_range_it_within_ten_percent(start):
    scene, model = _scene(), _model()
    eyes = eye_positions(HEAD, np.zeros(3), LENGTH)
    fixations = []
    for eye in eyes:
        def look(theta, phi, eye=eye):
            return render_eye(scene, eye, gaze_rotation(HEAD, theta, phi))
        fixation = foveate(look, model, *start)
        assert fixation.foveated, fixation
        fovea = look(fixation.theta, fixation.phi)[3]
        centre = fovea[30:34, 30:34]
        assert (centre[..., 0] > 60).all() and (centre[..., 1] < 40).all()  # red, not yellow
        fixations.append(fixation)
    left = fixations[0]
    fixations[1] = correlate(render_eye(scene, eyes[0], gaze_rotation(HEAD, left.theta,
                                                                     left.phi))[3],
                             lambda theta, phi: render_eye(scene, eyes[1],
                                                           gaze_rotation(HEAD, theta, phi)),
                             fixations[1])
    baseline = float(np.linalg.norm(eyes[0] - eyes[1]))
    vergence, distance = verge(*fixations, baseline)
    target = scene.bodies[0][1]
    truth = np.linalg.norm(target.mean(axis=0) - eyes.mean(axis=0))
    assert vergence > 0
    assert distance == pytest.approx(truth, rel=0.1), (distance, truth)


def test_nothing_is_detected_in_empty_water():
    levels = render_eye(_scene(with_target=False), np.zeros(3), gaze_rotation(HEAD, 0.0, 0.0))
    assert detect(levels, _model())[0] == -1
    assert RetinaParams().levels == 4
