"""``animat figures``: the paper's vision figures from a short pursuit."""

import cv2

from animat.experiments import cli


def test_figures_are_written(tmp_path, capsys):
    assert cli.main(["figures", "--out", str(tmp_path), "--frames", "16"]) == 0
    fig5 = cv2.imread(str(tmp_path / "fig5_retinas.png"))
    assert fig5.shape == (512, 1280, 3)
    assert cv2.imread(str(tmp_path / "fig7_gaze.png")) is not None
    assert cv2.imread(str(tmp_path / "fig8_sequence.png")).shape == (512, 1024, 3)
    assert "fovea_fraction" in capsys.readouterr().out
    assert cli.main(["figures", "--out", str(tmp_path), "--frames", "2"]) == 2
