"""The fish's swim is drawn as a path coloured by time (issue 28, item 7), not a cloud of
red dots: a tube along the frames, dark (viridis) at the start, yellow at the end."""

from __future__ import annotations

import numpy as np

from growsim.models.fish import develop


def _near(img: np.ndarray, rgb, tol: int = 40) -> int:
    return int((np.abs(img.astype(int) - np.asarray(rgb)).max(axis=-1) < tol).sum())


def test_the_swim_is_a_path_coloured_by_time():
    traj = develop({"frames": 3000})
    img = traj.render_image(view="top", size=(240, 200))
    assert _near(img, (68, 1, 84)) > 20  # viridis' start (dark purple)
    assert _near(img, (253, 231, 37)) > 20  # viridis' end (yellow)
    assert _near(img, (217, 31, 26), tol=30) == 0  # no red dots


def test_a_long_swim_is_thinned_to_a_bounded_path():
    from growsim.phenotypes import trajectory

    traj = develop({"frames": 3 * trajectory.MAX_PATH_POINTS})
    line = traj.path_line()
    frames = line.point_data["frame"]
    assert frames[0] == 0 and frames[-1] == len(traj.positions) - 1
    assert line.n_points <= trajectory.MAX_PATH_POINTS + 1
    assert line.n_lines >= 1 and (np.diff(frames) > 0).all()
