#!/usr/bin/env python3
"""How well the inverse model reaches a photographed albedo: the Lee Perry-Smith head's skin texels.

Fits the head's albedo (Map-COL.jpg) with `spectral_skin.fit_texture` and counts, over the skin
texels only, the share within 1 CIEDE2000 of the model's colour and the share with each
parameter on a bound of its range. Skin texels are the texels the mesh's triangles cover in
texture space (LeePerrySmith.glb, TEXCOORD_0; the image's row 0 at v = 1, as `skin render` and
the web page read this head's textures); the fill around the UV islands is not skin. The data are third-party assets read from ../shared/data (never
committed); without them the script says so and stops.

Usage (from the root of a checkout, with the Python module built in build/python):

    PYTHONPATH=build/python /usr/bin/python3 scripts/lps_texture_fit.py [--model extended]
        [--free melanin,melanin_blend,...] [--mask-png mask.png]

prints one line per quantity (docs/fit.md, "Texture fit" quotes them).
"""
import argparse
import json
import os
import struct
import sys
import time

import numpy as np

import spectral_skin as ss


def read_glb_uv_triangles(path):
    """Texture coordinates of every triangle of every mesh primitive of a .glb: (T, 3, 2)."""
    with open(path, "rb") as f:
        data = f.read()
    magic, _, length = struct.unpack_from("<4sII", data, 0)
    if magic != b"glTF" or length != len(data):
        raise SystemExit(f"{path}: not a binary glTF file")
    offset, doc, binary = 12, None, b""
    while offset < length:
        size, kind = struct.unpack_from("<I4s", data, offset)
        chunk = data[offset + 8: offset + 8 + size]
        if kind == b"JSON":
            doc = json.loads(chunk)
        elif kind == b"BIN\x00":
            binary = chunk
        offset += 8 + size
    kinds = {5121: np.uint8, 5123: np.uint16, 5125: np.uint32, 5126: np.float32}
    widths = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}

    def accessor(i):
        a = doc["accessors"][i]
        view = doc["bufferViews"][a["bufferView"]]
        dtype = np.dtype(kinds[a["componentType"]])
        width = widths[a["type"]]
        start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
        stride = view.get("byteStride", 0) or dtype.itemsize * width
        rows = np.ndarray((a["count"], width), dtype=dtype, buffer=binary, offset=start, strides=(stride, dtype.itemsize))
        return np.array(rows)

    triangles = []
    for mesh in doc["meshes"]:
        for prim in mesh["primitives"]:
            if prim.get("mode", 4) != 4 or "TEXCOORD_0" not in prim["attributes"]:
                continue
            uv = accessor(prim["attributes"]["TEXCOORD_0"]).astype(float)
            index = accessor(prim["indices"]).reshape(-1) if "indices" in prim else np.arange(len(uv))
            triangles.append(uv[index.reshape(-1, 3)])
    if not triangles:
        raise SystemExit(f"{path}: no triangles with texture coordinates")
    return np.concatenate(triangles)


def rasterise(triangles, width, height):
    """Texels whose centre lies in a triangle of texture space (u right, v up the image)."""
    mask = np.zeros((height, width), bool)
    pts = np.stack([triangles[..., 0] * width, (1.0 - triangles[..., 1]) * height], axis=-1)
    for (ax, ay), (bx, by), (cx, cy) in pts:
        x0, x1 = int(max(0, np.floor(min(ax, bx, cx)))), int(min(width - 1, np.ceil(max(ax, bx, cx))))
        y0, y1 = int(max(0, np.floor(min(ay, by, cy)))), int(min(height - 1, np.ceil(max(ay, by, cy))))
        if x1 < x0 or y1 < y0:
            continue
        X, Y = np.meshgrid(np.arange(x0, x1 + 1) + 0.5, np.arange(y0, y1 + 1) + 0.5)
        d = (by - cy) * (ax - cx) + (cx - bx) * (ay - cy)
        if abs(d) < 1e-12:
            continue
        l1 = ((by - cy) * (X - cx) + (cx - bx) * (Y - cy)) / d
        l2 = ((cy - ay) * (X - cx) + (ax - cx) * (Y - cy)) / d
        inside = (l1 >= 0) & (l2 >= 0) & (l1 + l2 <= 1)
        mask[y0:y1 + 1, x0:x1 + 1] |= inside
    return mask


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data-dir", default=os.path.join("..", "shared", "data", "meshes", "LeePerrySmith"))
    parser.add_argument("--model", default="paper", choices=["paper", "extended"])
    parser.add_argument("--free", default=None, help="comma-separated parameter keys (default: the model's)")
    parser.add_argument("--mask-png", default=None, help="also write the skin mask as a PNG")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="a fixed parameter's value (e.g. dermis_scattering_scale=1); repeatable")
    a = parser.parse_args()
    texture = os.path.join(a.data_dir, "Map-COL.jpg")
    mesh = os.path.join(a.data_dir, "LeePerrySmith.glb")
    if not (os.path.isfile(texture) and os.path.isfile(mesh)):
        print(f"the Lee Perry-Smith head is not in {a.data_dir}: nothing to measure")
        return 0
    options = {"model": a.model}
    if a.free:
        options["free"] = a.free.split(",")
    for item in a.set:
        key, _, value = item.partition("=")
        options[key] = float(value)
    start = time.time()
    maps = ss.fit_texture(texture, **options)
    seconds = time.time() - start
    height, width = maps["error"].shape
    mask = rasterise(read_glb_uv_triangles(mesh), width, height)
    if a.mask_png:
        import matplotlib.pyplot as plt
        plt.imsave(a.mask_png, mask, cmap="gray")
    error = maps["error"][mask]
    print(f"model {a.model}, free {','.join(options.get('free', [])) or 'default'}"
          f"{''.join(', ' + item for item in a.set)}: fit {seconds:.1f} s")
    print(f"skin texels (covered by the mesh's triangles): {mask.sum()} of {mask.size} ({mask.mean():.1%})")
    print(f"within 1 dE2000: {np.mean(error < 1):.1%} of skin texels (all texels {maps['error_delta_e_2000']['fraction_below_1']:.1%})")
    print(f"dE2000 over skin texels: median {np.median(error):.2f}, mean {error.mean():.2f}, "
          f"90th percentile {np.percentile(error, 90):.2f}")
    for name in maps["channels"]:
        if name == "error":
            continue
        v = maps[name][mask]
        print(f"{name}: 5th-95th percentile {np.percentile(v, 5):.4g}-{np.percentile(v, 95):.4g}, "
              f"median {np.median(v):.4g}, on a bound {maps['at_bound'].get(name, 0) / mask.size:.1%} of all texels")
    return 0


if __name__ == "__main__":
    sys.exit(main())
