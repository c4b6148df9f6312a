"""A plant among copies of itself (growsim.kernels.copies; oracles in tests/naive/copies.py):
the moved points listed as the oracle lists them, and hard exposures among copies equal
to the exact geometry away from a shadow's edge."""

from __future__ import annotations

import numpy as np
import pytest
from naive import copies as naive
from test_light import points_near, population

from growsim.env.light import view_basis
from growsim.kernels import copies as kernels
from growsim.kernels.light import plant_frames, shadow_scratch
from growsim.kernels.stand import periodic_shifts

#: lights from above, a little from the side
SUNS = ([0.4, -1.0, 0.1], [0.0, -1.0, 0.0], [-0.3, -1.0, 0.5])


def scene(seed, res):
    """Two random plants, points near them, one light, and copies close enough to
    overlap: ``(segments, frames, plane, targets, shifts)``."""
    rng = np.random.default_rng(400 + seed)
    start, end, radius, offsets = population(rng, 2, 50)
    radius = 3.0 * radius  # thick branches: much of the stand in shade
    segments = (start, end, radius, offsets)
    points, point_offsets, _ = points_near(rng, segments, 150)
    d = np.array(SUNS[seed])
    d /= np.linalg.norm(d)
    u, v = view_basis(d)
    frames = plant_frames(start, end, radius, offsets, u, v, res)
    spread = float(np.ptp(np.concatenate([start, end])[:, [0, 2]], axis=0).max())
    shifts = periodic_shifts(0.4 * spread, 2, 3)
    return segments, frames, (u, v, d), (points, point_offsets), shifts


@pytest.mark.parametrize("seed", range(3))
def test_the_moved_points_are_the_oracles(seed):
    _, frames, (u, v, _), (points, point_offsets), shifts = scene(seed, 64)
    got = kernels.among_copies(points, point_offsets, frames, (u, v, 64), shifts)
    want = naive.among_copies(points, point_offsets, frames, (u, v, 64), shifts)
    for a, b in zip(got, want, strict=True):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12)
    assert len(points) < len(got[2]) < len(points) * (len(shifts) + 1)  # some fall outside


@pytest.mark.parametrize("seed", range(3))
def test_hard_exposures_among_copies_match_the_oracle(seed):
    segments, frames, plane, targets, shifts = scene(seed, 96)
    scratch = shadow_scratch(96)
    got = kernels.copies_hard(segments, frames, plane, (96, 0.5), targets, shifts, scratch,
                              np.full(len(targets[0]), np.nan))  # fmt: skip
    want = naive.copies_hard(segments, plane, (96, 0.5), targets, shifts)
    edge = naive.copies_hard(segments, plane, (96, 0.5), targets, shifts, tol_pixels=1.0)
    assert np.all((got == want) | edge)
    assert np.mean(~edge) > 0.3  # enough points judged
    assert 0.1 < np.mean(want[~edge] == 0) < 0.9  # lit and shaded points both
    assert not scratch[1].any()  # the occupancy words left as given
    alone = naive.copies_hard(segments, plane, (96, 0.5), targets, np.zeros((0, 3)))
    assert (want < alone).mean() > 0.02  # the copies shade points the plant leaves lit
