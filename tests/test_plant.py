"""The Plant skeleton: validation, measures on hand-checked shapes, persistence."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

from growsim.errors import UserInputError
from growsim.phenotypes.plant import LEAF, STEM, Plant


def _fork():
    # trunk 0->2 up, two branches to (+-1, 3)
    pts = [[0, 0, 0], [0, 2, 0], [1, 3, 0], [-1, 3, 0]]
    return Plant.from_points(pts, [-1, 0, 0], [-1, 0, 1, 1], radius=[0.2, 0.1, 0.1])


def test_counts_and_extents():
    p = _fork()
    assert (p.n_segments, p.n_tips, p.n_branch_points) == (3, 2, 1)
    assert p.height() == 3.0 and p.crown_width() == 2.0 and p.crown_depth() == 0.0
    assert p.bbox().tolist() == [[-1, 0, 0], [1, 3, 0]]
    assert p.total_length() == pytest.approx(2 + 2 * math.sqrt(2))
    m = p.measures()
    assert m["n_tips"] == 2 and m["height"] == 3.0


def test_leaves_do_not_count_as_tips():
    pts = [[0, 0, 0], [0, 1, 0], [0.5, 1.2, 0]]
    p = Plant.from_points(pts, [-1, 0], [-1, 0, 1], kind=[STEM, LEAF])
    assert p.n_tips == 1 and p.n_leaves == 1 and p.n_stems == 1
    assert p.total_length() == 1.0
    assert p.total_length(kinds=None) == pytest.approx(1 + math.hypot(0.5, 0.2))


@pytest.mark.parametrize(
    "field,value,msg",
    [
        ("start", np.zeros((2, 2)), "start"),
        ("end", np.full((2, 3), np.nan), "end"),
        ("radius", [-1.0, 0.1], "negative"),
        ("parent", [-1, 5], "parent"),
        ("parent", [0, -1], "parent"),  # self-parent
        ("kind", [0, 7], "kind"),
        ("order", [0], "order"),
    ],
)
def test_validation_names_the_field(field, value, msg):
    kw = dict(
        start=np.zeros((2, 3)),
        end=np.ones((2, 3)),
        radius=[0.1, 0.1],
        parent=[-1, 0],
        order=[0, 1],
        kind=[0, 0],
    )
    kw[field] = value
    with pytest.raises(UserInputError, match=msg):
        Plant(**kw)


def test_data_rows_checked():
    with pytest.raises(UserInputError, match="light"):
        Plant(
            np.zeros((2, 3)),
            np.ones((2, 3)),
            [1, 1],
            [-1, 0],
            [0, 0],
            [0, 0],
            data={"light": np.zeros(3)},
        )


def test_wood_volume_cone_and_cylinder():
    cyl = Plant.from_points([[0, 0, 0], [0, 2, 0]], [-1], [-1, 0], radius=0.5)
    assert cyl.wood_volume() == pytest.approx(math.pi * 0.25 * 2)
    cone = Plant(cyl.start, cyl.end, [0.5], [-1], [0], [0], data={"radius_end": np.array([0.0])})
    assert cone.wood_volume() == pytest.approx(math.pi * 0.25 * 2 / 3)


def test_projected_area_known_shapes():
    from growsim.env.light import projected_area

    def area(p, **kw):
        return projected_area(p.start, p.end, p.radius, **kw)

    # a vertical pole seen from above is a disc
    pole = Plant.from_points([[0, 0, 0], [0, 5, 0]], [-1], [-1, 0], radius=1.0)
    assert area(pole, resolution=512) == pytest.approx(math.pi, rel=0.02)
    # seen from the front it is a 2 x 5 rectangle with round caps (2 x 5 + pi)
    side = area(pole, direction=(0, 0, -1), resolution=512)
    assert side == pytest.approx(10 + math.pi, rel=0.02)
    # two far apart horizontal rods from above: areas add
    rods = Plant.from_points(
        [[0, 0, 0], [4, 0, 0], [0, 0, 10], [4, 0, 10]], [-1, -1], [-1, 0, -1, 2], radius=0.5
    )
    assert area(rods, resolution=1024) == pytest.approx(2 * (4 + math.pi / 4), rel=0.03)
    # leaves only
    p = _fork()
    assert p.leaf_area() == 0.0
    with pytest.raises(UserInputError, match="direction"):
        area(p, direction=(0, 0, 0))


def test_concat_subset():
    a = _fork()
    both = Plant.concat([a, a], offsets=[[0, 0, 0], [10, 0, 0]])
    assert both.n_segments == 6 and both.parent.tolist() == [-1, 0, 0, -1, 3, 3]
    assert both.crown_width() == 12.0
    sub = both.subset(both.parent >= 0)
    assert sub.parent.tolist() == [-1, -1, -1, -1]


def test_save_load_roundtrip(tmp_path):
    p = _fork()
    p.data["light"] = np.array([0.1, 0.2, 0.3])
    p.meta = {"model": "x", "params": {"f": np.float64(0.5)}}
    f = p.save(tmp_path / "p.npz")
    q = Plant.load(f)
    for name in ("start", "end", "radius", "parent", "order", "kind"):
        assert np.array_equal(getattr(p, name), getattr(q, name))
        assert getattr(p, name).dtype == getattr(q, name).dtype
    assert np.array_equal(q.data["light"], p.data["light"])
    assert q.meta == {"model": "x", "params": {"f": 0.5}}
    assert os.listdir(tmp_path) == ["p.npz"]  # no temporary left behind


def test_save_errors(tmp_path):
    p = _fork()
    with pytest.raises(UserInputError, match="does not exist"):
        p.save(tmp_path / "missing" / "p.npz")
    with pytest.raises(UserInputError, match="npz"):
        p.save(tmp_path / "p.txt")
    (tmp_path / "bad.npz").write_bytes(b"not a zip")
    with pytest.raises(UserInputError, match=r"bad\.npz"):
        Plant.load(tmp_path / "bad.npz")
