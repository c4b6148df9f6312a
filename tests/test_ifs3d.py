"""The IFS tree kernels and model against slow NumPy oracles."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from growsim.errors import ResourceError, UserInputError
from growsim.kernels import ifs3d as K
from growsim.models import ifs3d
from growsim.plant import Plant

# ----------------------------------------------------------------------------- oracles


def naive_map(s, y, tz, ty):
    """4x4 homogeneous Trans(0,y,0) Rot_y(ty) Rot_z(-tz) Scale(s), degrees."""
    a, b = np.radians(-tz), np.radians(ty)
    T = np.eye(4)
    T[1, 3] = y
    Ry = np.eye(4)
    Ry[[0, 0, 2, 2], [0, 2, 0, 2]] = [np.cos(b), np.sin(b), -np.sin(b), np.cos(b)]
    Rz = np.eye(4)
    Rz[[0, 0, 1, 1], [0, 1, 0, 1]] = [np.cos(a), -np.sin(a), np.sin(a), np.cos(a)]
    S = np.diag([s, s, s, 1.0])
    return T @ Ry @ Rz @ S


def naive_tree(maps, depth):
    """Every composition w_j1 ... w_jk (OS), level by level, lexicographic inside a level."""
    W = [naive_map(*m) for m in maps]
    O = np.array([0, 0, 0, 1.0])
    S = np.array([0, 1, 0, 1.0])
    starts, ends = [], []
    for k in range(depth + 1):
        for js in itertools.product(range(len(maps)), repeat=k):
            M = np.eye(4)
            for j in js:
                M = M @ W[j]
            starts.append((M @ O)[:3])
            ends.append((M @ S)[:3])
    return np.array(starts), np.array(ends)


def naive_frame(start, end, base, size):
    pts = np.concatenate([start, end])
    h = pts[:, 1].max() - pts[:, 1].min()
    hw = max(np.abs(pts[:, 0] - base[0]).max(), np.abs(pts[:, 2] - base[2]).max())
    k = np.inf
    if h > 0:
        k = (size - 2 * K.MARGIN) / h
    if hw > 0:
        k = min(k, (size / 2 - K.MARGIN) / hw)
    if not np.isfinite(k):
        k = 1.0
    out = np.empty((2, 2, len(start), 2))
    for e, P in enumerate((start, end)):
        row = size - K.MARGIN - k * (P[:, 1] - pts[:, 1].min())
        out[0, e, :, 0] = size / 2 + k * (P[:, 0] - base[0])
        out[1, e, :, 0] = size / 2 - k * (P[:, 2] - base[2])
        out[:, e, :, 1] = row
    return out, k


def naive_render(coords, size):
    img = np.zeros((2, size, size), np.uint8)
    for v in range(2):
        for (ax, ay), (bx, by) in zip(coords[v, 0], coords[v, 1]):
            dx, dy = bx - ax, by - ay
            n = max(1, int(np.ceil(max(abs(dx), abs(dy)))))
            f = np.arange(n + 1) * (1.0 / n)
            x, y = ax + dx * f, ay + dy * f
            ok = (x >= 0) & (y >= 0) & (x < size) & (y < size)
            img[v, y[ok].astype(int), x[ok].astype(int)] = 1
    return img


def naive_score(maps, depth, target, area_reject):
    s, e = naive_tree(maps, depth)
    c, _ = naive_frame(s, e, np.zeros(3), target.shape[1])
    F = naive_render(c, target.shape[1]).astype(bool)
    G = target.astype(bool)
    v = [
        (F[i] & G[i]).sum() / np.sqrt(F[i].sum() * G[i].sum()) if F[i].sum() else 0.0
        for i in range(2)
    ]
    if area_reject and not 0.5 <= F.sum() / G.sum() <= 2.0:
        return 0.0
    return float(np.mean(v))


def naive_render_aa(coords, size):
    """Anti-aliased lines: each sample's ink (segment length / samples) spread bilinearly."""
    acc = np.zeros((2, size, size))
    for v in range(2):
        for (ax, ay), (bx, by) in zip(coords[v, 0], coords[v, 1]):
            dx, dy = bx - ax, by - ay
            n = max(1, int(np.ceil(max(abs(dx), abs(dy)))))
            ink = np.hypot(dx, dy) / (n + 1)
            for t in range(n + 1):
                x, y = ax + dx * (t / n) - 0.5, ay + dy * (t / n) - 0.5
                j0, i0 = int(np.floor(x)), int(np.floor(y))
                for ii, wy in ((i0, 1 - (y - i0)), (i0 + 1, y - i0)):
                    for jj, wx in ((j0, 1 - (x - j0)), (j0 + 1, x - j0)):
                        if 0 <= ii < size and 0 <= jj < size:
                            acc[v, ii, jj] += ink * wx * wy
    return np.minimum(acc, 1.0)


def naive_blur(img, sigma):
    """Separable Gaussian (taps to 3 sigma, zero outside) by explicit 2D convolution."""
    r = int(np.ceil(3 * sigma))
    g = np.exp(-0.5 * (np.arange(-r, r + 1) / sigma) ** 2)
    k2 = np.outer(g, g) / g.sum() ** 2
    out = np.zeros(img.shape)
    V, S0, S1 = img.shape
    pad = np.zeros((V, S0 + 2 * r, S1 + 2 * r))
    pad[:, r : r + S0, r : r + S1] = img
    for i in range(S0):
        for j in range(S1):
            out[:, i, j] = (pad[:, i : i + 2 * r + 1, j : j + 2 * r + 1] * k2).sum(axis=(1, 2))
    return out


def naive_blurred_score(maps, depth, target, sigma):
    s, e = naive_tree(maps, depth)
    c, _ = naive_frame(s, e, np.zeros(3), target.shape[1])
    F = naive_blur(naive_render_aa(c, target.shape[1]), sigma)
    G = naive_blur(target.astype(float), sigma)
    v = [(F[i] * G[i]).sum() / np.sqrt((F[i] ** 2).sum() * (G[i] ** 2).sum()) for i in range(2)]
    return float(np.mean(v))


def random_maps(rng, n, N=5):
    m = np.empty((n, N, 4))
    m[..., 0] = rng.uniform(0.1, 0.7, (n, N))
    m[..., 1] = rng.uniform(0.2, 1.0, (n, N))
    m[..., 2] = rng.uniform(0, 90, (n, N))
    m[..., 3] = rng.uniform(0, 360, (n, N))
    return m


TABLE1 = ifs3d.maps_from_params(ifs3d.PRESETS["table1"])

# ----------------------------------------------------------------------------- kernels


def test_map_matrices_match_oracle():
    rng = np.random.default_rng(0)
    maps = random_maps(rng, 1, 7)[0]
    maps[0, 2:] = [0.0, 0.0]
    maps[1, 2:] = [90.0, 360.0]
    W = K.map_matrices(maps)
    for w, m in zip(W, maps):
        np.testing.assert_allclose(w, naive_map(*m)[:3], atol=1e-14)


@pytest.mark.parametrize(("N", "depth"), [(1, 0), (1, 4), (2, 3), (3, 3), (5, 1), (5, 3), (4, 4)])
def test_compose_matches_oracle(N, depth):
    rng = np.random.default_rng(N * 10 + depth)
    maps = random_maps(rng, 1, N)[0]
    s, e = K.compose_tree(maps, depth)
    s0, e0 = naive_tree(maps, depth)
    assert s.shape == (K.n_segments(N, depth), 3)
    np.testing.assert_allclose(s, s0, atol=1e-12)
    np.testing.assert_allclose(e, e0, atol=1e-12)


@pytest.mark.parametrize("seed", range(3))
def test_frame_and_render_match_oracle(seed):
    rng = np.random.default_rng(seed)
    s, e = K.compose_tree(random_maps(rng, 1, 3)[0], 3)
    base = rng.normal(0, 0.1, 3) if seed else np.zeros(3)
    c, k = K.frame_points(s, e, base, 48)
    c0, k0 = naive_frame(s, e, base, 48)
    np.testing.assert_allclose(c, c0, atol=1e-10)
    assert k == pytest.approx(k0)
    # every framed point lies inside the raster, the extremes on pixel centres
    assert c.min() >= K.MARGIN - 1e-9 and c.max() <= 48 - K.MARGIN + 1e-9
    img = np.empty((2, 48, 48), np.uint8)
    K._render(c, img)
    np.testing.assert_array_equal(img, naive_render(c, 48))


def test_frame_degenerate_and_trunk_only():
    c, k = K.frame_points(np.zeros((1, 3)), np.zeros((1, 3)), np.zeros(3), 16)
    assert k == 1.0 and c[0, 0, 0].tolist() == [8.0, 15.5]
    img = K.render_views(*K.compose_tree(TABLE1[:1], 0), np.zeros(3), 16)
    # the bare trunk: the centre column, top to bottom, in both views
    assert img[:, :, 8].all() and img.sum() == 32


@pytest.mark.parametrize("area", [False, True])
def test_score_population_matches_oracle(area):
    rng = np.random.default_rng(5)
    target = K.render_views(*K.compose_tree(random_maps(rng, 1, 3)[0], 3), np.zeros(3), 32)
    pop = random_maps(rng, 12, 3)
    got = K.score_population(pop, 3, target, area)
    want = [naive_score(m, 3, target, area) for m in pop]
    np.testing.assert_allclose(got, want, atol=1e-12)
    assert K.score_population(pop[:0], 3, target).shape == (0,)


@pytest.mark.parametrize("seed", range(2))
def test_antialiased_render_and_blur_match_oracle(seed):
    rng = np.random.default_rng(seed + 20)
    s, e = K.compose_tree(random_maps(rng, 1, 3)[0], 3)
    c, _ = K.frame_points(s, e, np.zeros(3), 24)
    acc = np.empty((2, 24, 24))
    K._render_aa(c, acc)
    np.testing.assert_allclose(acc, naive_render_aa(c, 24), atol=1e-12)
    assert acc.max() <= 1.0 and acc.sum() > 0
    for sigma in (0.6, 1.5):
        np.testing.assert_allclose(K.blur_views(acc, sigma), naive_blur(acc, sigma), atol=1e-12)
        binary = (acc > 0.3).astype(np.uint8)
        np.testing.assert_allclose(
            K.blur_views(binary, sigma), naive_blur(binary.astype(float), sigma), atol=1e-12
        )
    with pytest.raises(ValueError, match="sigma"):
        K.gaussian_taps(0.0)


def test_blurred_score_matches_oracle_and_is_smoother():
    rng = np.random.default_rng(7)
    target = K.render_views(*K.compose_tree(random_maps(rng, 1, 3)[0], 3), np.zeros(3), 32)
    pop = random_maps(rng, 6, 3)
    got = K.score_population(pop, 3, target, False, 1.2)
    want = [naive_blurred_score(m, 3, target, 1.2) for m in pop]
    np.testing.assert_allclose(got, want, atol=1e-12)
    # a branch shifted by a fraction of a pixel: the binary score jumps, the blurred one
    # changes a little and continuously
    s, e = K.compose_tree(TABLE1, 5)
    t64 = K.render_views(s, e, np.zeros(3), 64)
    y = TABLE1[1, 1] + np.linspace(-0.03, 0.03, 13)
    pop = np.repeat(TABLE1[None], 13, axis=0)
    pop[:, 1, 1] = y
    hard = K.score_population(pop, 5, t64)
    soft = K.score_population(pop, 5, t64, False, 1.0)
    assert hard[6] == 1.0 and soft[6] > 0.99
    assert np.abs(np.diff(soft)).max() < 0.5 * np.abs(np.diff(hard)).max()
    assert soft.min() > hard.min()
    with pytest.raises(ValueError, match="blur"):
        K.score_population(pop, 5, t64, False, -1.0)


def test_score_is_one_on_its_own_target_and_lower_elsewhere():
    s, e = K.compose_tree(TABLE1, 5)
    target = K.render_views(s, e, np.zeros(3), 64)
    pert = TABLE1.copy()
    pert[2, 3] += 20.0
    sc = K.score_population(np.stack([TABLE1, pert]), 5, target)
    assert sc[0] == 1.0 and sc[1] < 0.99


def test_kernel_input_checks():
    with pytest.raises(ValueError, match="shape"):
        K.compose_tree(np.zeros((2, 3)), 2)
    with pytest.raises(ValueError, match="depth"):
        K.compose_tree(TABLE1, -1)
    with pytest.raises(ValueError, match="params"):
        K.score_population(np.zeros((2, 4)), 2, np.zeros((2, 8, 8), np.uint8))
    with pytest.raises(ValueError, match="target"):
        K.score_population(TABLE1[None], 2, np.zeros((8, 8), np.uint8))


# ----------------------------------------------------------------------------- model


def test_develop_table1_plant():
    tree = ifs3d.develop(ifs3d.PRESETS["table1"], seed=3)
    assert isinstance(tree, Plant)
    assert tree.n_segments == 3906
    s0, e0 = naive_tree(TABLE1, 5)
    np.testing.assert_allclose(tree.start, s0, atol=1e-12)
    np.testing.assert_allclose(tree.end, e0, atol=1e-12)
    # every child starts on its parent segment, one level deeper
    i = np.arange(1, tree.n_segments)
    p = tree.parent[i]
    assert (tree.parent[0] == -1) and (p < i).all()
    d = tree.end[p] - tree.start[p]
    v = tree.start[i] - tree.start[p]
    assert np.abs(np.cross(d, v)).max() < 1e-12
    t = (v * d).sum(1) / (d * d).sum(1)
    assert t.min() >= 0.4 - 1e-9 and t.max() <= 0.4 + 1e-9
    np.testing.assert_array_equal(tree.order[i], tree.order[p] + 1)
    # radius proportional to length; symmetric crown
    length = np.linalg.norm(tree.end - tree.start, axis=1)
    np.testing.assert_allclose(tree.radius, ifs3d.RADIUS_RATIO * length)
    assert tree.height() == pytest.approx(1.0)
    assert tree.crown_width() == pytest.approx(tree.crown_depth())
    assert tree.meta["model"] == "ifs3d" and tree.meta["seed"] == 3


def test_param_spec_and_defaults():
    names = [p.name for p in ifs3d.PARAMS]
    assert names[:2] == ["n_maps", "depth"] and len(names) == 22
    by = {p.name: p for p in ifs3d.PARAMS}
    # the seed's ranges
    assert (by["y_1"].low, by["y_1"].high) == (0.3, 0.6)
    assert (by["theta_y_3"].low, by["theta_y_3"].high) == (90.0, 180.0)
    assert (by["theta_y_1"].low, by["theta_y_1"].high) == (0.0, 360.0)
    spec3 = ifs3d.param_spec({"n_maps": 3})
    assert len(spec3) == 2 + 12
    assert {p.name: p for p in spec3}["theta_y_3"].low == 180.0
    tree = ifs3d.develop({"n_maps": 3, "depth": 2})
    assert tree.n_segments == 13
    for name, preset in ifs3d.PRESETS.items():
        assert ifs3d.develop(preset).n_segments == 3906, name


def test_develop_errors():
    with pytest.raises(UserInputError, match="s_1"):
        ifs3d.develop({"s_1": 0.9})
    with pytest.raises(UserInputError, match="theta_z_9"):
        ifs3d.develop({"theta_z_9": 1.0})
    with pytest.raises(UserInputError, match="n_maps"):
        ifs3d.develop({"n_maps": 2.5})
    with pytest.raises(ResourceError, match="segments"):
        ifs3d.develop({"n_maps": 12, "depth": 10})


def test_compare_maps_symmetries():
    ref = TABLE1
    assert ifs3d.compare_maps(ref, ref, azimuth_period=90)["within"]
    # map order does not matter; the leader's azimuth counts modulo 90 for table1
    fit = ref[[0, 3, 1, 4, 2]].copy()
    fit[0, 3] = 180.0
    r = ifs3d.compare_maps(fit, ref, azimuth_period=90)
    assert r["within"] and r["order"].tolist() == [0, 2, 4, 1, 3]
    assert not ifs3d.compare_maps(fit, ref)["within"] or fit[0, 3] % 360 == 0
    far = ref.copy()
    far[1, 2] = 52.0
    r = ifs3d.compare_maps(far, ref, azimuth_period=90)
    assert not r["within"] and r["max_error"][2] == pytest.approx(7.0)
    # azimuths wrap around the circle
    wrap = ref.copy()
    wrap[4, 3] = 268.0
    wrap[1, 3] = 358.0
    assert ifs3d.compare_maps(wrap, ref)["max_error"][3] == pytest.approx(2.0)
    with pytest.raises(UserInputError):
        ifs3d.compare_maps(ref[:3], ref)
