"""Meshes: kernel vs oracle, LOD, export formats and errors."""

from __future__ import annotations

import itertools
import json
import os
import struct

import numpy as np
import pytest
import pyvista as pv
from naive.mesh import leaf as leaf_oracle
from naive.mesh import tube as tube_oracle

from growsim.errors import UserInputError
from growsim.kernels.mesh import mesh_counts, mesh_kernel, weld_targets
from growsim.models import honda
from growsim.phenotypes.plant import LEAF, STEM, Plant, cluster_leaves
from growsim.phenotypes.plant.mesh import (
    export,
    lod_meshes,
    mesh_arrays,
    plant_mesh,
)


def _random_plant(rng, n=40, leaf_frac=0.3):
    start = rng.normal(size=(n, 3)) * 5
    end = start + rng.normal(size=(n, 3))
    # edge cases: axis-aligned segments (frame helper ties) and a zero-length stem
    end[0] = start[0] + [0, 2, 0]
    end[1] = start[1] + [3, 0, 0]
    end[2] = start[2]
    kind = (rng.random(n) < leaf_frac).astype(np.int8)
    kind[:3] = STEM
    kind[3] = LEAF
    end[3] = start[3] + [0, 0, 1.5]
    r0 = rng.random(n) * 0.5
    r1 = r0 * rng.random(n)
    return start, end, r0, r1, kind


@pytest.mark.parametrize("sides,segments", [(3, 1), (6, 2), (8, 3), (5, 4)])
def test_mesh_kernel_matches_oracle(sides, segments):
    rng = np.random.default_rng(sides * 10 + segments)
    start, end, r0, r1, kind = _random_plant(rng)
    no_weld = np.full(len(kind), -1, np.int64)
    pts, tris, vkind = mesh_kernel(start, end, r0, r1, kind, sides, segments, no_weld)
    nv, nt = mesh_counts(int((kind == 0).sum()), int((kind == 1).sum()), sides, segments)
    assert pts.shape == (nv, 3) and tris.shape == (nt, 3)
    expect = [
        tube_oracle(start[s], end[s], r0[s], r1[s], sides, segments)
        for s in range(len(kind))
        if kind[s] == 0
    ]
    expect += [leaf_oracle(start[s], end[s], r0[s]) for s in range(len(kind)) if kind[s] == 1]
    np.testing.assert_allclose(pts, np.concatenate(expect), atol=1e-5)
    n_bark = int((kind == 0).sum()) * sides * (segments + 1)
    assert vkind[:n_bark].sum() == 0 and np.all(vkind[n_bark:] == 1)
    assert tris.min() >= 0 and tris.max() < nv
    # every triangle is non-degenerate apart from the zero-length / zero-radius ones
    m = pv.PolyData.from_regular_faces(pts, tris)
    assert m.n_points == nv


def test_tube_rings_have_the_radius():
    p = Plant.from_points(
        [[0, 0, 0], [1, 1, 1]], [-1], [-1, 0], radius=0.3, data={"radius_end": np.array([0.1])}
    )
    pts, _, _ = mesh_arrays(p, sides=7, segments=2)
    axis = np.array([1, 1, 1]) / np.sqrt(3)
    for j, r in enumerate([0.3, 0.2, 0.1]):
        ring = pts[j * 7 : (j + 1) * 7].astype(float)
        c = axis * np.sqrt(3) * j / 2
        d = ring - c
        assert np.allclose(d @ axis, 0, atol=1e-6)
        assert np.allclose(np.linalg.norm(d, axis=1), r, atol=1e-6)


def test_plant_mesh_kind_and_counts():
    t = honda.develop(honda.PRESETS["zelkova"])
    m = plant_mesh(t, sides=6, segments=1)
    kind = np.asarray(m.point_data["kind"])
    assert m.n_points == t.n_stems * 12 + t.n_leaves * 7
    assert int(kind.sum()) == t.n_leaves * 7
    assert plant_mesh(t, leaves=False).n_points == t.n_stems * 12
    with pytest.raises(UserInputError, match="sides"):
        plant_mesh(t, sides=2)


def test_lod_falls_and_keeps_silhouette():
    t = honda.develop(honda.PRESETS["plane"])
    ms = lod_meshes(t)
    counts = [m.n_points for m in ms]
    assert all(a > b for a, b in itertools.pairwise(counts)), counts
    b0 = np.array(ms[0].bounds)
    for m in ms[1:]:
        # same extent within a leaf size
        assert np.abs(np.array(m.bounds) - b0).max() < 4.0
    c = cluster_leaves(t)
    assert c.n_stems == t.n_stems and c.n_leaves == t.n_leaves // 3
    # clustering keeps the total blade area (radius x length per leaf) of each branch
    la = (t.radius * t.lengths())[t.kind == LEAF].sum()
    lc = (c.radius * c.lengths())[c.kind == LEAF].sum()
    assert lc == pytest.approx(la, rel=0.05)
    with pytest.raises(UserInputError, match="unknown"):
        lod_meshes(t, levels=[{"sides": 4, "bogus": 1}])


@pytest.mark.parametrize("suffix", [".vtp", ".ply", ".obj", ".glb"])
def test_export_formats(tmp_path, suffix):
    t = honda.develop(honda.PRESETS["h_columnar"])
    path = export(t, tmp_path / f"tree{suffix}")
    assert path.exists() and path.stat().st_size > 0
    assert sorted(os.listdir(tmp_path)) == [f"tree{suffix}"]
    n = t.n_stems * 12 + t.n_leaves * 7
    if suffix == ".glb":
        data = path.read_bytes()
        magic, version, total = struct.unpack("<4sII", data[:12])
        assert (magic, version, total) == (b"glTF", 2, len(data))
        jlen, jtype = struct.unpack("<I4s", data[12:20])
        doc = json.loads(data[20 : 20 + jlen])
        blen, btype = struct.unpack("<I4s", data[20 + jlen : 28 + jlen])
        assert (jtype, btype) == (b"JSON", b"BIN\x00") and blen == doc["buffers"][0]["byteLength"]
        assert [nd["name"] for nd in doc["nodes"]] == ["bark", "leaf"]
        acc = doc["accessors"]
        pos = [acc[m["primitives"][0]["attributes"]["POSITION"]]["count"] for m in doc["meshes"]]
        assert pos == [t.n_stems * 12, t.n_leaves * 7]
        idx = acc[doc["meshes"][1]["primitives"][0]["indices"]]
        assert idx["count"] == t.n_leaves * 6 * 3
        # the leaf positions decoded from the binary chunk are the mesh's leaf vertices
        view = doc["bufferViews"][
            acc[doc["meshes"][1]["primitives"][0]["attributes"]["POSITION"]]["bufferView"]
        ]
        off = 28 + jlen + view["byteOffset"]
        leaf_pts = np.frombuffer(data[off : off + view["byteLength"]], np.float32).reshape(-1, 3)
        m = plant_mesh(t)
        want = np.asarray(m.points)[np.asarray(m.point_data["kind"]) == 1]
        np.testing.assert_allclose(np.sort(leaf_pts, axis=0), np.sort(want, axis=0))
        return
    m = pv.read(path)
    assert m.n_points == n
    if suffix == ".vtp":
        assert int(np.asarray(m.point_data["kind"]).sum()) == t.n_leaves * 7
    else:
        rgb = np.asarray(m.point_data["RGB"])
        green = (rgb[:, 1] > rgb[:, 0]).sum()
        assert green == t.n_leaves * 7
    if suffix == ".obj":
        text = path.read_text()
        assert "g bark" in text and "g leaf" in text


def test_export_errors(tmp_path):
    t = honda.develop({"generations": 3})
    with pytest.raises(UserInputError, match="unknown mesh format"):
        export(t, tmp_path / "t.stl")
    with pytest.raises(UserInputError, match="does not exist"):
        export(t, tmp_path / "nope" / "t.glb")
    with pytest.raises(UserInputError, match="does not exist"):
        export(t, tmp_path / "nope" / "t.obj")
    with pytest.raises(UserInputError, match="empty"):
        export(Plant.empty(), tmp_path / "e.ply")
    (tmp_path / "file").write_text("x")
    for suffix in (".vtp", ".ply", ".obj", ".glb"):
        with pytest.raises(UserInputError, match="file"):
            export(t, tmp_path / "file" / f"t{suffix}")
    assert os.listdir(tmp_path) == ["file"]


@pytest.mark.parametrize("sides,segments", [(3, 1), (6, 2)])
def test_merged_tubes_match_unmerged(sides, segments):
    t = honda.develop({**honda.PRESETS["plane"], "generations": 7})
    r1 = t.radius_end()
    weld = weld_targets(t.parent, t.kind, t.radius)
    stems = np.flatnonzero(t.kind == STEM)
    # oracle for the weld choice: each stem parent's thickest stem child (first on ties)
    for p in stems:
        kids = [s for s in stems if t.parent[s] == p]
        if kids:
            best = max(kids, key=lambda s: (t.radius[s], -s))
            assert weld[best] == p and all(weld[k] == -1 for k in kids if k != best)
    args = (t.start, t.end, t.radius, r1, t.kind, sides, segments)
    p0, t0, k0 = mesh_kernel(*args, np.full(t.n_segments, -1, np.int64))
    p1, t1, k1 = mesh_kernel(*args, weld)
    n_weld = int((weld >= 0).sum())
    assert p1.shape[0] == p0.shape[0] - n_weld * sides and t1.shape == t0.shape
    # drop each welded stem's own base ring from the unmerged mesh: the rest is identical
    ring = sides * (segments + 1)
    keep = np.ones(p0.shape[0], bool)
    for i, s in enumerate(stems):
        if weld[s] >= 0:
            keep[i * ring : i * ring + sides] = False
    np.testing.assert_array_equal(p1, p0[keep])
    assert np.array_equal(k1, k0[keep])
    # triangles: same corners, except a welded base ring is now the parent's end ring
    new_index = np.cumsum(keep) - 1
    ends = {s: i * ring + segments * sides for i, s in enumerate(stems)}
    remap = new_index.copy()
    for i, s in enumerate(stems):
        if weld[s] >= 0:
            base = i * ring
            remap[base : base + sides] = new_index[ends[weld[s]] : ends[weld[s]] + sides]
    np.testing.assert_array_equal(t1, remap[t0])
    # the merged mesh is watertight along an axis: fewer boundary edges than unmerged
    m0 = pv.PolyData.from_regular_faces(p0, t0).extract_feature_edges(
        boundary_edges=True, feature_edges=False, manifold_edges=False, non_manifold_edges=False
    )
    m1 = pv.PolyData.from_regular_faces(p1, t1).extract_feature_edges(
        boundary_edges=True, feature_edges=False, manifold_edges=False, non_manifold_edges=False
    )
    assert m1.n_cells < m0.n_cells
