"""One tree render in every form a user's picture comes in (issue 41), read and segmented.

A photo render (``benchmarks/make_photos.py``: a dark-barked bare tree, ``g_tall_trunk``,
on a ground plane under a blue sky, JPEG-compressed; 512 px) and a drawing of the same
tree (its true silhouette, black on white) are saved as: a plain 8-bit PNG (the
reference), a JPEG, a 16-bit grey PNG, a palette PNG, an RGBA PNG with a transparent
background (the drawing's paper transparent; the photo's pale pixels half transparent,
so that over white they are the plain picture), a 1-bit PNG (the drawing), a grey JPEG,
a CMYK JPEG (with black generation), a JPEG whose pixels are turned a quarter with EXIF
orientation 6 (as a phone saves a portrait photo), and enlarged to 1024 (the working
size), 3000 and 6000 px (the photo as JPEG, the drawing as PNG). For each form: the kind
:func:`growsim.pictures.images.classify_picture` chooses; the silhouette of the
segmentation the fit uses for that kind (``photo`` or ``threshold``), its IoU against the
plain PNG's (an enlarged form's silhouette reduced to the plain size, a pixel set when at
least half covered) and against its reference's (:func:`measure`); the seconds to read,
classify and segment it, with the ratio to the plain picture's and the reference's. Then
the seconds until what will be refused is (a uniform 6000 px picture, a truncated JPEG, a
5 px picture), and a summary. Prints JSON lines.

    python benchmarks/picture_forms.py                 # 512 px render, 1024, 3000, 6000
    python benchmarks/picture_forms.py --size 256 --enlarge 1024 3000
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

__all__ = ["FORMS", "drawing_of", "read_as_viewed", "silhouette_of", "write_forms"]

#: the forms every picture is saved in (besides ``enlarged_<N>``); ``one_bit`` for
#: drawings only
FORMS = ("png", "jpeg", "png16_grey", "palette", "rgba", "one_bit", "grey_jpeg",
         "cmyk_jpeg", "exif_rotated")  # fmt: skip
#: grey forms: they read to the plain picture's grey levels
GREY_FORMS = ("png16_grey", "grey_jpeg", "one_bit")


def drawing_of(truth: np.ndarray) -> np.ndarray:
    """A render's true silhouette as a drawing: ``(H, W, 3)`` uint8, black on white."""
    g = np.where(truth, 0, 255).astype(np.uint8)
    return np.repeat(g[..., None], 3, axis=2)


def _cmyk(rgb: np.ndarray):
    """A PIL CMYK image of ``rgb`` (uint8) with full black generation: K = 1 - max(R, G,
    B), C = (1 - R - K) / (1 - K), ... (a print's separation, not Pillow's K = 0)."""
    from PIL import Image

    x = rgb.astype(np.float64) / 255.0
    k = 1.0 - x.max(axis=2)
    cmy = (1.0 - x - k[..., None]) / np.maximum(1.0 - k, 1e-9)[..., None]
    cmyk = np.concatenate([cmy, k[..., None]], axis=2)
    return Image.fromarray(np.round(255 * np.clip(cmyk, 0, 1)).astype(np.uint8), mode="CMYK")


def write_forms(rgb: np.ndarray, out: Path, *, drawing: bool, enlarge=(3000,)) -> dict:
    """Save the picture ``rgb`` ``(H, W, 3)`` uint8 in every form of :data:`FORMS` (and
    ``enlarged_<N>`` for each ``N`` of ``enlarge``) into ``out``; returns name -> path.
    ``drawing``: the picture is a drawing (grey forms in L, the paper transparent, a 1-bit
    form, enlargements as PNG)."""
    from PIL import Image, ImageOps

    out.mkdir(parents=True, exist_ok=True)
    im = Image.fromarray(rgb)
    grey = im.convert("L")
    paths = {}

    def save(name, image, ext, **kw):
        paths[name] = out / f"{name}.{ext}"
        image.save(paths[name], **kw)

    save("png", grey if drawing else im, "png")
    save("jpeg", grey if drawing else im, "jpg", quality=92)
    deep = np.asarray(grey, dtype=np.uint16) * 257
    save("png16_grey", Image.fromarray(deep), "png")
    assert Image.open(paths["png16_grey"]).mode == "I;16"
    if drawing:
        save("palette", grey.convert("P"), "png")
        rgba = np.zeros((*rgb.shape[:2], 4), np.uint8)  # transparent black paper
        rgba[..., 3] = 255 - np.asarray(grey)
        save("rgba", Image.fromarray(rgba, mode="RGBA"), "png")
        save("one_bit", grey.convert("1", dither=Image.Dither.NONE), "png")
    else:  # a GIF's 256 colours (median cut posterizes the sky's gradient into bands)
        save("palette", im.quantize(256, method=Image.Quantize.FASTOCTREE,
                                    dither=Image.Dither.NONE), "png")  # fmt: skip
        # pale pixels half transparent, of the colour that over white is theirs
        rgba = np.concatenate([rgb, np.full((*rgb.shape[:2], 1), 255, np.uint8)], axis=2)
        pale = (rgb >= 128).all(axis=2)
        rgba[pale, :3] = 2 * rgb[pale].astype(np.int64) - 255
        rgba[pale, 3] = 128
        save("rgba", Image.fromarray(rgba, mode="RGBA"), "png")
    save("grey_jpeg", grey, "jpg", quality=92)
    save("cmyk_jpeg", _cmyk(rgb), "jpg", quality=95)
    assert Image.open(paths["cmyk_jpeg"]).mode == "CMYK"
    # a phone's portrait photo: the pixels stored turned a quarter to the left, the tag
    # saying "turn them a quarter to the right to view"
    exif = Image.Exif()
    exif[274] = 6
    save("exif_rotated", im.transpose(Image.Transpose.ROTATE_90), "jpg", quality=92,
         exif=exif.tobytes())  # fmt: skip
    with Image.open(paths["exif_rotated"]) as check:
        assert ImageOps.exif_transpose(check).size == im.size
    for n in enlarge:
        big = (grey if drawing else im).resize((n, n), Image.Resampling.LANCZOS)
        save(f"enlarged_{n}", big, "png" if drawing else "jpg", quality=92)
    return paths


def read_as_viewed(path) -> np.ndarray:
    """The picture's RGB at the working size (:func:`growsim.pictures.reading.load_rgb`)."""
    from growsim.pictures.reading import load_rgb

    return load_rgb(path)


def silhouette_of(path, kind: str) -> np.ndarray:
    """The silhouette the fit reads from the picture at ``path`` for its ``kind``: the
    photo segmentation (``"photo"``) or the threshold (``"drawing"``), uncached."""
    from growsim.pictures.images import silhouette
    from growsim.pictures.photo import segment_photo

    if kind == "photo":
        return segment_photo(path).tree
    return silhouette(path)


def to_size(mask: np.ndarray, shape) -> np.ndarray:
    """A silhouette at another size: each pixel set when at least half covered (area)."""
    from PIL import Image

    im = Image.fromarray(mask.astype(np.float32), mode="F")
    small = im.resize((shape[1], shape[0]), Image.Resampling.BOX)
    return np.asarray(small) >= 0.5


def iou(a: np.ndarray, b: np.ndarray) -> float:
    """Intersection over union of two silhouettes (``b``'s size: ``a`` is resized)."""
    if a.shape != b.shape:
        a = to_size(a, b.shape)
    return float((a & b).sum() / max(1, (a | b).sum()))


def measure(paths: dict, expected: str, repeat: int = 3) -> list[dict]:
    """One row per form: the kind chosen, the IoU of its silhouette (the segmentation for
    ``expected``, the render's kind) against the plain PNG's and against its reference's
    (``reference``: what it should equal if reading is exact, through the same
    segmentation: a grey form, the plain picture's grey levels; the EXIF-turned JPEG, the
    same JPEG unturned; an enlargement beyond the working size, the same enlargement made
    at the working size, ``enlarged_1024``), the seconds to read it, to classify it and
    to segment it (reading the file again, as a fit's first segmentation does; the least
    of ``repeat`` runs) and the ratio of the last to the plain picture's (and to the
    reference's)."""
    from growsim.pictures.images import classify_picture
    from growsim.pictures.reading import WORK_SIZE, forget, load_gray

    silhouette_of(paths["png"], expected)  # warm: imports, compiled kernels
    rows, masks, seconds = [], {}, {}
    masks["grey"] = _segmented(load_gray(paths["png"]), expected)
    for name, path in paths.items():
        forget()
        t0 = time.perf_counter()
        read = read_as_viewed(path)
        t1 = time.perf_counter()
        kind, why = classify_picture(path)
        t2 = time.perf_counter()
        times = []
        for _ in range(repeat):  # the least of a few: the machine is shared
            forget()  # the segmentation reads the file itself, as a fit's first one does
            t3 = time.perf_counter()
            try:
                masks[name], error = silhouette_of(path, expected), None
            except Exception as exc:  # a refusal is a result here
                masks[name], error = None, str(exc)
            times.append(time.perf_counter() - t3)
        seconds[name] = min(times)
        row = {"form": name, "render": expected, "file_kb": round(path.stat().st_size / 1024),
               "working_shape": list(read.shape[:2]), "kind": kind, "why": why,
               "read_seconds": round(t1 - t0, 3), "classify_seconds": round(t2 - t1, 3),
               "segment_seconds": round(seconds[name], 3),
               "time_ratio": round(seconds[name] / seconds["png"], 2)}  # fmt: skip
        if masks[name] is None:
            row["refused"] = error
            rows.append(row)
            continue
        row["iou"] = round(iou(masks[name], masks["png"]), 4)
        ref = {"exif_rotated": "jpeg"}.get(name, "grey" if name in GREY_FORMS else None)
        big = name.startswith("enlarged_") and name != f"enlarged_{WORK_SIZE}"
        ref = f"enlarged_{WORK_SIZE}" if big else ref
        if ref is not None and masks.get(ref) is not None:
            row["reference"] = ref
            row["iou_reference"] = round(iou(masks[name], masks[ref]), 4)
            if ref in seconds:
                row["time_ratio_reference"] = round(seconds[name] / seconds[ref], 2)
        rows.append(row)
    return rows


def _segmented(grey: np.ndarray, kind: str) -> np.ndarray:
    """The silhouette of grey levels (an array) for the render's ``kind``."""
    from growsim.pictures.images import silhouette
    from growsim.pictures.photo import segment_photo

    return segment_photo(grey).tree if kind == "photo" else silhouette(grey)


def refusals(out: Path) -> list[dict]:
    """Seconds until ``growsim fit-image``'s reading refuses what it will refuse: a
    uniform 6000 x 6000 px photo (PNG), a truncated JPEG, a 5 x 5 px picture (the
    segmentation's checks on the picture read at the working size)."""
    from PIL import Image

    from growsim.errors import UserInputError
    from growsim.pictures.images import classify_picture, picture_silhouettes

    out.mkdir(parents=True, exist_ok=True)
    Image.new("RGB", (6000, 6000), (200, 210, 230)).save(out / "uniform_6000.png")
    Image.new("RGB", (5, 5), (200, 210, 230)).save(out / "tiny.png")
    photo = np.random.default_rng(0).integers(0, 255, (600, 800, 3), dtype=np.uint8)
    Image.fromarray(photo).save(out / "whole.jpg")
    (out / "truncated.jpg").write_bytes((out / "whole.jpg").read_bytes()[:3000])
    rows = []
    for name in ("uniform_6000.png", "truncated.jpg", "tiny.png"):
        t0 = time.perf_counter()
        try:
            kind, _ = classify_picture(out / name)
            seg = "photo" if kind == "photo" else "threshold"
            picture_silhouettes(out / name, segmentation=seg)
            message = None
        except UserInputError as exc:
            message = str(exc).replace(str(out) + "/", "")
        rows.append({"kind": "refusal", "picture": name, "refused": message,
                     "seconds": round(time.perf_counter() - t0, 3)})  # fmt: skip
    return rows


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--size", type=int, default=512, help="the render's size (px)")
    ap.add_argument("--picture", type=int, default=4,
                    help="which of make_photos.PICTURES (4: g_tall_trunk_bare)")  # fmt: skip
    ap.add_argument("--enlarge", type=int, nargs="*", default=[1024, 3000, 6000])
    ap.add_argument("--out", type=Path, default=None, help="keep the pictures here")
    ap.add_argument("--repeat", type=int, default=3, help="segmentations timed (the least)")
    args = ap.parse_args(argv)
    from make_photos import PICTURES, make_photo

    rgb, truth, _ = make_photo(PICTURES[args.picture], size=args.size)
    with tempfile.TemporaryDirectory() as tmp:
        out = args.out or Path(tmp)
        rows = []
        for kind, picture in (("photo", rgb), ("drawing", drawing_of(truth))):
            paths = write_forms(picture, out / kind, drawing=kind == "drawing",
                                enlarge=args.enlarge)  # fmt: skip
            for row in measure(paths, kind, args.repeat):
                print(json.dumps(row), flush=True)
                rows.append(row)
        refused = refusals(out / "refused")
        for row in refused:
            print(json.dumps(row), flush=True)
    ok = [r for r in rows if r["form"] != "png"]
    big = [r for r in ok if r.get("reference", "").startswith("enlarged")]
    same_size = [r.get("iou", 0.0) for r in ok if not r["form"].startswith("enlarged")]
    summary = {
        "kind": "summary",
        "picture": PICTURES[args.picture].name,
        "size": args.size,
        "forms": len(ok),
        "kind_right": sum(r["kind"] == r["render"] for r in ok),
        "min_iou": min(r.get("iou", 0.0) for r in ok),
        "min_iou_not_enlarged": min(same_size),
        "min_iou_reference": min(r["iou_reference"] for r in ok if "iou_reference" in r),
        "min_iou_enlarged_vs_working_size": min((r["iou_reference"] for r in big), default=None),
        "max_time_ratio_enlarged_vs_working_size": max(
            (r["time_ratio_reference"] for r in big), default=None
        ),
        "max_segment_seconds": max(r["segment_seconds"] for r in rows),
        "max_refusal_seconds": max(r["seconds"] for r in refused),
    }
    print(json.dumps(summary))


if __name__ == "__main__":
    main()
