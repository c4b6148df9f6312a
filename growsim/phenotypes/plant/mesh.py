"""Plant -> pyvista mesh: n-gon tubes and hexagon leaves, levels of detail, export.

- :func:`plant_mesh`: one triangle mesh with ``point_data["kind"]`` (0 bark, 1 leaf) and,
  on request, per-segment values carried onto its triangles as ``cell_data`` (``fields``:
  the light, stress or water a view colours the plant by); a plant of modules (segments
  with ``chlorophyll`` and ``lignin``: the hormone model) also gets each triangle's tissue
  colour (``cell_data["rgb"]``), a leaf blade on each module that acts as a leaf
  (:func:`leaf_modules`) and the soil's height (``field_data["ground"]``);
- :func:`ground_mesh`: the soil slab a view draws under such a plant;
- :func:`triangle_segments`: the segment each triangle of a mesh belongs to;
- :func:`lod_meshes`: one skeleton, several meshes of falling vertex count (fewer tube
  sides and pieces, leaves clustered) with the same silhouette;
- :func:`export`: ``.vtp``, ``.ply``, ``.obj`` or ``.glb`` by suffix, written atomically.

The tube and leaf geometry follow the seed "C G による枝ぶり生成法" (section 4.3); the hot
loop is :func:`growsim.kernels.mesh.mesh_kernel`.

A plant (:class:`growsim.phenotypes.plant.Plant`) is read here through its arrays and
methods (``start``, ``end``, ``radius``, ``parent``, ``kind``, ``data``, ``meta``,
``radius_end()``, ``subset()``, ``cluster_leaves()``) and recognised by :func:`is_plant`:
this module does not import the class, whose module imports this one.
"""

from __future__ import annotations

import json
import os
import struct
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from growsim.errors import UserInputError
from growsim.files import atomic_path, atomic_write
from growsim.kernels.mesh import LEAF_TRIS, mesh_kernel, weld_targets
from growsim.phenotypes.base import Phenotype
from growsim.phenotypes.plant.colors import tissue_rgb
from growsim.skeleton import LEAF

__all__ = [
    "BARK_RGB",
    "DEFAULT_LODS",
    "LEAF_RGB",
    "export",
    "ground_mesh",
    "is_plant",
    "leaf_modules",
    "lod_meshes",
    "mesh_arrays",
    "module_plant",
    "plant_mesh",
    "triangle_segments",
]

#: vertex colours written to exports (bark brown, leaf green), uint8 RGB
BARK_RGB = (110, 82, 58)
LEAF_RGB = (74, 140, 58)

#: a blade's area over its length times its half-width (the hexagon of :func:`_blades`)
BLADE_AREA = 1.26

#: a module acts as a leaf (drawn with a blade) with at least this chlorophyll and less
#: than this lignin (:func:`leaf_modules`)
LEAF_CHLOROPHYLL = 0.5
LEAF_LIGNIN = 0.5

#: default levels of detail, finest first
DEFAULT_LODS: tuple[dict, ...] = (
    {"sides": 8, "segments": 3},
    {"sides": 6, "segments": 2, "merge": True},
    {"sides": 4, "segments": 1, "merge": True, "cluster": True},
    {"sides": 3, "segments": 1, "merge": True, "cluster": True},
)


def is_plant(obj) -> bool:
    """Whether ``obj`` is a plant: a phenotype of kind ``"plant"``
    (:class:`growsim.phenotypes.plant.Plant`), checked without importing the class.

    Examples
    --------
    >>> from growsim.phenotypes.plant import Plant
    >>> is_plant(Plant.empty()), is_plant("a tree")
    (True, False)
    """
    return isinstance(obj, Phenotype) and obj.phenotype == "plant"


def _check_plant(plant):
    if not is_plant(plant):
        raise UserInputError(f"expected a growsim Plant, got {type(plant).__name__}")
    return plant


def module_plant(plant) -> bool:
    """Whether ``plant`` is a plant of modules that carry ``chlorophyll`` and ``lignin``
    (the hormone model's): drawn by tissue, with leaf blades and the soil.

    Examples
    --------
    >>> from growsim.phenotypes.plant import Plant
    >>> p = Plant.from_points([[0, 0, 0], [0, 1, 0]], [-1], [-1, 0])
    >>> module_plant(p)
    False
    """
    return is_plant(plant) and {"chlorophyll", "lignin"} <= set(plant.data)


def leaf_modules(plant) -> np.ndarray:
    """``(n,)`` bool: the modules of a :func:`module_plant` that act as leaves, drawn with
    a blade: those with leaves (``data["leaf_area"] > 0``, the hormone model's growsim
    physics); else (its paper physics, where every module photosynthesises in proportion
    to its chlorophyll and lignin turns it to wood, ``docs/models/hormone.md``) a module
    with chlorophyll at least :data:`LEAF_CHLOROPHYLL` and lignin under
    :data:`LEAF_LIGNIN`. All ``False`` for other plants.

    Examples
    --------
    >>> from growsim.phenotypes.plant import Plant
    >>> p = Plant.from_points([[0, 0, 0], [0, 1, 0], [0, 2, 0]], [-1, 0], [-1, 0, 1],
    ...                       data={"chlorophyll": [0.2, 0.9], "lignin": [0.8, 0.1]})
    >>> leaf_modules(p).tolist()
    [False, True]
    """
    if not module_plant(plant):
        return np.zeros(plant.n_segments, bool)
    if np.any(plant.data.get("leaf_area", 0.0)):  # leaves as organs (growsim physics)
        return (plant.kind != LEAF) & (np.asarray(plant.data["leaf_area"]) > 0)
    c = np.asarray(plant.data["chlorophyll"], dtype=np.float64)
    g = np.asarray(plant.data["lignin"], dtype=np.float64)
    return (plant.kind != LEAF) & (c >= LEAF_CHLOROPHYLL) & (g < LEAF_LIGNIN)


def _blades(plant, idx: np.ndarray):
    """Leaf blades along modules ``idx``: a flat hexagon from the module's start to its
    end (7 vertices, 6 triangles, as the mesh kernel's leaves), half as wide as the
    module's wall is round (``pi r``, at most a third of its length: one side of the
    blade about the wall's area) or, for modules with a leaf area (``data["leaf_area"]``:
    the hormone model's growsim physics), as wide as makes the blade's area that leaf
    area; lying in the plant's plane for a flat (2D) plant, facing up as far as the
    module allows in 3D. Returns ``(points, tris)``."""
    a, b = plant.start[idx], plant.end[idx]
    d = b - a
    L = np.linalg.norm(d, axis=1)
    u = d / np.maximum(L, 1e-12)[:, None]
    flat = bool(np.all(plant.start[:, 2] == 0) and np.all(plant.end[:, 2] == 0))
    ref = np.array([0.0, 0.0, 1.0]) if flat else np.array([0.0, 1.0, 0.0])
    across = np.cross(u, ref)
    norm = np.linalg.norm(across, axis=1)
    vertical = norm < 1e-9  # (3D) a vertical module: across along x
    across[vertical] = (1.0, 0.0, 0.0)
    across /= np.maximum(np.linalg.norm(across, axis=1), 1e-12)[:, None]
    if np.any(plant.data.get("leaf_area", 0.0)):  # the blade's area is the leaf area
        area = np.asarray(plant.data["leaf_area"], dtype=np.float64)[idx]
        w = (area / (BLADE_AREA * np.maximum(L, 1e-12)))[:, None]
    else:
        w = np.minimum(np.pi * plant.radius[idx], L / 3.0)[:, None]
    outline = [(0.0, 0.0), (0.3, 0.8), (0.7, 1.0), (1.0, 0.0), (0.7, -1.0), (0.3, -0.8)]
    pts = [a + 0.5 * d]  # the centre, then the outline
    pts += [a + t * d + s * w * across for t, s in outline]
    pts = np.stack(pts, axis=1).reshape(-1, 3)
    base = 7 * np.arange(len(idx))[:, None, None]
    fan = np.array([[0, 1 + i, 1 + (i + 1) % 6] for i in range(6)])
    return pts.astype(np.float32), (base + fan[None]).reshape(-1, 3).astype(np.int64)


def ground_mesh(bounds, height: float):
    """The soil under a plant: a flat slab (``pyvista.Box``) whose top is the plane
    ``y = height``, a little wider than the plant's footprint ``bounds`` (xmin, xmax,
    ymin, ymax, zmin, zmax) and square, about 3 % of the plant's height thick.

    Examples
    --------
    >>> box = ground_mesh((-1, 1, 0, 4, 0, 0), 0.0)
    >>> [round(v, 3) for v in box.bounds]
    [-1.6, 1.6, -0.12, 0.0, -1.6, 1.6]
    """
    import pyvista as pv

    b = np.asarray(bounds, float).reshape(3, 2)
    top = max(float(b[1, 1]) - float(height), 1e-6)
    cx, cz = b[0].mean(), b[2].mean()
    half = max(np.ptp(b[0]), np.ptp(b[2])) / 2.0 + 0.15 * top
    thick = 0.03 * top
    return pv.Box((cx - half, cx + half, height - thick, height, cz - half, cz + half))


def mesh_arrays(plant, sides: int = 6, segments: int = 1, leaves: bool = True, merge: bool = False):
    """The raw mesh of ``plant``: ``points`` ``(N, 3)`` float32, ``tris`` ``(M, 3)``
    int64, ``kind`` ``(N,)`` uint8 (0 bark, 1 leaf). See :func:`plant_mesh`; a
    :func:`module_plant` gets a leaf blade (``kind`` 1) after its tubes for each module of
    :func:`leaf_modules` (with ``leaves``).

    Examples
    --------
    >>> from growsim.phenotypes.plant import Plant
    >>> p = Plant.from_points([[0, 0, 0], [0, 1, 0]], [-1], [-1, 0])
    >>> pts, tris, kind = mesh_arrays(p, sides=4, segments=1)
    >>> pts.shape, tris.shape
    ((8, 3), (8, 3))
    """
    plant = _check_plant(plant)
    sides, segments = int(sides), int(segments)
    if not 3 <= sides <= 64:
        raise UserInputError(f"mesh sides: {sides} not in [3, 64]")
    if not 1 <= segments <= 64:
        raise UserInputError(f"mesh segments: {segments} not in [1, 64]")
    r1 = plant.radius_end()
    parent = plant.parent
    arrays = (plant.start, plant.end, plant.radius, r1, plant.kind)
    if not leaves:
        keep = plant.kind != LEAF
        arrays = tuple(a[keep] for a in arrays)
        parent = plant.subset(keep).parent if merge else parent[keep]
    arrays = tuple(np.ascontiguousarray(a) for a in arrays)
    if merge:
        weld = weld_targets(np.ascontiguousarray(parent), arrays[4], arrays[2])
    else:
        weld = np.full(arrays[4].shape[0], -1, np.int64)
    pts, tris, kind = mesh_kernel(*arrays, sides, segments, weld)
    blade = np.flatnonzero(leaf_modules(plant)) if leaves else np.zeros(0, np.int64)
    if blade.size:
        bp, bt = _blades(plant, blade)
        tris = np.concatenate([tris, bt + pts.shape[0]])
        pts = np.concatenate([pts, bp])
        kind = np.concatenate([kind, np.ones(bp.shape[0], kind.dtype)])
    return pts, tris, kind


def triangle_segments(plant, sides: int = 6, segments: int = 1, leaves: bool = True):
    """``(M,)`` int64: the segment of ``plant`` each triangle of its mesh belongs to (the
    mesh of :func:`plant_mesh` / :func:`mesh_arrays` with the same ``sides``, ``segments``
    and ``leaves``; ``merge`` changes vertices, not triangles). The mesh kernel lays out
    the stems first, in segment order, ``2 * sides * segments`` triangles each, then the
    leaves in segment order, 6 each, then the blades of a :func:`module_plant`'s
    :func:`leaf_modules`, 6 each.

    Examples
    --------
    >>> from growsim.phenotypes.plant import Plant
    >>> p = Plant.from_points([[0, 0, 0], [0, 1, 0], [1, 1, 0], [0, 2, 0]],  # stem, leaf,
    ...                       [-1, 0, 0], [-1, 0, 1, 1], kind=[0, 1, 0])   # stem
    >>> t = triangle_segments(p, sides=3)
    >>> t.tolist() == [0] * 6 + [2] * 6 + [1] * 6, t.size == mesh_arrays(p, sides=3)[1].shape[0]
    (True, True)
    """
    plant = _check_plant(plant)
    sides, segments = int(sides), int(segments)
    stems = np.flatnonzero(plant.kind != LEAF)
    leafs = np.flatnonzero(plant.kind == LEAF) if leaves else np.zeros(0, np.int64)
    blades = np.flatnonzero(leaf_modules(plant)) if leaves else np.zeros(0, np.int64)
    return np.concatenate(
        [np.repeat(stems, 2 * sides * segments), np.repeat(leafs, LEAF_TRIS),
         np.repeat(blades, LEAF_TRIS)]
    ).astype(np.int64)  # fmt: skip


def plant_mesh(
    plant,
    sides: int = 6,
    segments: int = 1,
    leaves: bool = True,
    merge: bool = False,
    fields: Mapping[str, Sequence[float]] | None = None,
):
    """Triangle mesh (``pyvista.PolyData``) of a plant.

    Each stem is an open ``sides``-gon tube split into ``segments`` pieces, tapering from
    its radius to :meth:`growsim.phenotypes.plant.Plant.radius_end`; each leaf a flat hexagon (7
    vertices). ``point_data["kind"]`` is 0 for bark and 1 for leaf vertices.
    ``merge=True`` merges consecutive segments of one axis into one tube: a segment that
    continues its parent (its thickest stem child) starts from the parent's end ring
    instead of its own, saving ``sides`` vertices per joint without moving any vertex.

    ``fields``: ``{name: (n,) values}``, one value per segment of ``plant``; each becomes
    ``cell_data[name]`` (float64), every triangle carrying its segment's value
    (:func:`triangle_segments`), so a view colours each segment flat by it.

    A :func:`module_plant` (the hormone model's) is drawn by what its modules are: every
    module a tube, each that acts as a leaf (:func:`leaf_modules`) also a flat leaf blade
    along it; ``cell_data["rgb"]`` (uint8) each triangle's tissue colour
    (:func:`growsim.phenotypes.plant.colors.tissue_rgb`: chlorophyll green to lignified
    brown) and ``field_data["ground"]`` the soil's height (``plant.meta["ground"]``,
    default 0), under which a view draws :func:`ground_mesh`.

    Examples
    --------
    >>> from growsim.phenotypes.plant import Plant
    >>> p = Plant.from_points([[0, 0, 0], [0, 1, 0]], [-1], [-1, 0])
    >>> m = plant_mesh(p, sides=6, segments=2)
    >>> m.n_points, int(m.point_data["kind"].sum())
    (18, 0)
    >>> m = plant_mesh(p, sides=3, fields={"light": [0.5]})
    >>> m.cell_data["light"].tolist()
    [0.5, 0.5, 0.5, 0.5, 0.5, 0.5]
    """
    import pyvista as pv

    pts, tris, kind = mesh_arrays(plant, sides=sides, segments=segments, leaves=leaves, merge=merge)
    values = {}
    for name, value in (fields or {}).items():
        arr = np.asarray(value, dtype=np.float64)
        if arr.shape != (plant.n_segments,):
            raise UserInputError(
                f"mesh field {name!r}: expected one value per segment, shape "
                f"({plant.n_segments},), got {arr.shape}"
            )
        values[str(name)] = arr
    if tris.shape[0] == 0:
        mesh = pv.PolyData(pts.astype(np.float32)) if pts.shape[0] else pv.PolyData()
    else:
        mesh = pv.PolyData.from_regular_faces(pts, tris)
    mesh.point_data["kind"] = kind
    modules = module_plant(plant)
    if (values or modules) and tris.shape[0]:
        seg = triangle_segments(plant, sides=sides, segments=segments, leaves=leaves)
        for name, arr in values.items():
            mesh.cell_data[name] = arr[seg]
        if modules:
            rgb = tissue_rgb(plant.data["chlorophyll"], plant.data["lignin"])
            mesh.cell_data["rgb"] = np.round(255.0 * rgb[seg]).astype(np.uint8)
    if modules:
        mesh.field_data["ground"] = np.array([float(plant.meta.get("ground", 0.0))])
    return mesh


def lod_meshes(plant, levels: Sequence[dict] = DEFAULT_LODS) -> list:
    """Meshes of one skeleton at falling levels of detail, finest first.

    ``levels``: dicts with ``sides``, ``segments`` and optional ``merge`` (consecutive
    segments of an axis share joint rings, see :func:`plant_mesh`) and ``cluster`` (merge
    each branch's leaves into one, :func:`growsim.phenotypes.plant.cluster_leaves`). The
    skeleton is shared, so every level keeps the plant's silhouette; only vertex counts
    fall.

    Examples
    --------
    >>> from growsim.models import honda
    >>> ms = lod_meshes(honda.develop(honda.PRESETS["plane"]))
    >>> counts = [m.n_points for m in ms]
    >>> counts == sorted(counts, reverse=True)
    True
    """
    plant = _check_plant(plant)
    clustered = None
    out = []
    for i, lv in enumerate(levels):
        unknown = set(lv) - {"sides", "segments", "cluster", "leaves", "merge"}
        if unknown:
            raise UserInputError(f"lod level {i}: unknown key(s) {sorted(unknown)}")
        p = plant
        if lv.get("cluster", False):
            if clustered is None:
                clustered = plant.cluster_leaves()
            p = clustered
        out.append(
            plant_mesh(
                p,
                sides=lv.get("sides", 6),
                segments=lv.get("segments", 1),
                leaves=lv.get("leaves", True),
                merge=lv.get("merge", False),
            )
        )
    return out


def _rgb(kind: np.ndarray) -> np.ndarray:
    return np.where(kind[:, None] == 1, np.array(LEAF_RGB), np.array(BARK_RGB)).astype(np.uint8)


def _write_obj(fh, mesh) -> None:
    pts = np.asarray(mesh.points)
    tris = mesh.regular_faces if mesh.n_cells else np.zeros((0, 3), np.int64)
    kind = np.asarray(mesh.point_data["kind"])
    rgb = _rgb(kind) / 255.0
    fh.write(b"# growsim plant mesh: groups bark and leaf; v x y z r g b\n")
    np.savetxt(fh, np.hstack([pts, rgb]), fmt="v %.6g %.6g %.6g %.3f %.3f %.3f")
    leaf_tri = kind[tris[:, 0]] == 1 if tris.size else np.zeros(0, bool)
    for name, sel in (("bark", ~leaf_tri), ("leaf", leaf_tri)):
        if sel.any():
            fh.write(f"g {name}\n".encode())
            np.savetxt(fh, tris[sel] + 1, fmt="f %d %d %d")


def export(plant_or_mesh, path: str | os.PathLike, **mesh_options) -> Path:
    """Write a plant (meshed with ``mesh_options``, see :func:`plant_mesh`) or a mesh to
    ``path``; the format follows the suffix:

    - ``.vtp``: VTK XML PolyData with the ``kind`` point array;
    - ``.ply``: binary PLY with per-vertex RGB colours (bark brown, leaf green);
    - ``.obj``: Wavefront OBJ with vertex colours and groups ``bark`` and ``leaf``;
    - ``.glb``: glTF binary (Blender, game engines) with two nodes, bark and leaves, with
      vertex colours.

    The file is written to a temporary name in the same directory and renamed, so it is
    never half-written. A bad suffix or an unwritable directory raises
    :class:`growsim.errors.UserInputError` naming the path.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from growsim.phenotypes.plant import Plant
    >>> p = Plant.from_points([[0, 0, 0], [0, 1, 0]], [-1], [-1, 0])
    >>> f = export(p, pathlib.Path(tempfile.mkdtemp()) / "t.vtp")
    >>> f.suffix
    '.vtp'
    """
    import pyvista as pv

    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in (".vtp", ".ply", ".obj", ".glb"):
        raise UserInputError(
            f"{path}: unknown mesh format {suffix!r}; use .vtp, .ply, .obj or .glb (the "
            "architecture as .mtg or .csv: growsim.phenotypes.plant.to_mtg, to_qsm_table)"
        )
    if is_plant(plant_or_mesh):
        mesh = plant_mesh(plant_or_mesh, **mesh_options)
    elif isinstance(plant_or_mesh, pv.PolyData):
        mesh = plant_or_mesh
        if "kind" not in mesh.point_data:
            mesh = mesh.copy()
            mesh.point_data["kind"] = np.zeros(mesh.n_points, np.uint8)
    else:
        raise UserInputError(
            f"export: expected a Plant or pyvista.PolyData, got {type(plant_or_mesh).__name__}"
        )

    if mesh.n_points == 0:
        raise UserInputError(f"{path}: nothing to export, the mesh is empty")
    if suffix == ".obj":
        return atomic_write(path, lambda fh: _write_obj(fh, mesh))
    if suffix == ".glb":
        return atomic_write(path, lambda fh: fh.write(_glb_bytes(mesh)))

    def write_to(tmp: Path) -> None:
        if suffix == ".vtp":
            mesh.save(tmp)
        elif suffix == ".ply":
            m = mesh.copy()
            m.point_data["rgb"] = _rgb(np.asarray(mesh.point_data["kind"]))
            m.save(tmp, texture="rgb")

    # VTK writers take a file name, not a file object: write a temporary file with the
    # right suffix in the target directory, then rename it over the target.
    try:
        with atomic_path(path) as tmp:
            write_to(tmp)
    except OSError as exc:
        raise UserInputError(f"{path}: the {suffix} writer failed ({exc})") from None
    return path


def _glb_bytes(mesh) -> bytes:
    """A glTF 2.0 binary (GLB) of ``mesh``: y up like growsim, one node and material per
    part (``bark``, ``leaf``), positions, per-vertex colours (``COLOR_0``) and uint32
    triangle indices. Written directly (VTK's exporter writes text glTF only)."""

    pts = np.asarray(mesh.points, dtype=np.float32)
    tris = mesh.regular_faces if mesh.n_cells else np.zeros((0, 3), np.int64)
    kind = np.asarray(mesh.point_data["kind"])
    blob = bytearray()
    views: list[dict] = []
    accessors: list[dict] = []
    meshes: list[dict] = []
    nodes: list[dict] = []
    materials: list[dict] = []

    def add_view(arr: np.ndarray, target: int) -> int:
        while len(blob) % 4:
            blob.append(0)
        views.append(
            {"buffer": 0, "byteOffset": len(blob), "byteLength": arr.nbytes, "target": target}
        )
        blob.extend(arr.tobytes())
        return len(views) - 1

    for value, rgb, name in ((0, BARK_RGB, "bark"), (1, LEAF_RGB, "leaf")):
        part = tris[kind[tris[:, 0]] == value] if tris.size else tris
        if part.shape[0] == 0:
            continue
        used, local = np.unique(part, return_inverse=True)
        p = np.ascontiguousarray(pts[used])
        col = np.tile(np.array((*rgb, 255), np.uint8), (p.shape[0], 1))
        idx = np.ascontiguousarray(local.reshape(-1).astype(np.uint32))
        a_pos = len(accessors)
        accessors.append(
            {
                "bufferView": add_view(p, 34962),
                "componentType": 5126,
                "count": int(p.shape[0]),
                "type": "VEC3",
                "min": p.min(0).tolist(),
                "max": p.max(0).tolist(),
            }
        )
        accessors.append(
            {
                "bufferView": add_view(col, 34962),
                "componentType": 5121,
                "normalized": True,
                "count": int(p.shape[0]),
                "type": "VEC4",
            }
        )
        accessors.append(
            {
                "bufferView": add_view(idx, 34963),
                "componentType": 5125,
                "count": int(idx.size),
                "type": "SCALAR",
            }
        )
        materials.append(
            {
                "name": name,
                "pbrMetallicRoughness": {
                    "baseColorFactor": [1.0, 1.0, 1.0, 1.0],
                    "metallicFactor": 0.0,
                    "roughnessFactor": 0.9,
                },
                "doubleSided": True,
            }
        )
        meshes.append(
            {
                "name": name,
                "primitives": [
                    {
                        "attributes": {"POSITION": a_pos, "COLOR_0": a_pos + 1},
                        "indices": a_pos + 2,
                        "material": len(materials) - 1,
                        "mode": 4,
                    }
                ],
            }
        )
        nodes.append({"name": name, "mesh": len(meshes) - 1})
    while len(blob) % 4:
        blob.append(0)
    doc = {
        "asset": {"version": "2.0", "generator": "growsim"},
        "scene": 0,
        "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob)}],
    }
    js = json.dumps(doc, separators=(",", ":")).encode()
    js += b" " * (-len(js) % 4)
    total = 12 + 8 + len(js) + (8 + len(blob) if blob else 0)
    out = bytearray(struct.pack("<4sII", b"glTF", 2, total))
    out += struct.pack("<I4s", len(js), b"JSON") + js
    if blob:
        out += struct.pack("<I4s", len(blob), b"BIN\x00") + bytes(blob)
    return bytes(out)
