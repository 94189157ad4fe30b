"""A tour of the 4-k hierarchy from Python: build it, measure every level's distance to
the input (symmetric Hausdorff, by CGAL), plot it with matplotlib when it is installed and
write a picture.

    python examples/python/hierarchy_tour.py [MESH] [OUT_DIR]

MESH defaults to ../shared/data/meshes/femur.off; the picture is OUT_DIR/hierarchy_tour.png
(a plot of the error per level, or without matplotlib the base domain rendered by asperity).
"""

import struct
import sys
import zlib
from pathlib import Path

import numpy as np

import asperity


def write_png(path: Path, rgba: np.ndarray) -> None:
    """An RGBA array as an 8-bit PNG (no imaging library needed)."""
    height, width, _ = rgba.shape
    rows = b"".join(b"\x00" + rgba[y].tobytes() for y in range(height))

    def chunk(kind: bytes, body: bytes) -> bytes:
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    header = struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


def main() -> None:
    here = Path(__file__).resolve().parents[2]
    mesh_path = Path(sys.argv[1]) if len(sys.argv) > 1 else here.parent / "shared/data/meshes/femur.off"
    out = Path(sys.argv[2]) if len(sys.argv) > 2 else Path("out")
    out.mkdir(parents=True, exist_ok=True)
    mesh = asperity.read(mesh_path)
    hierarchy = asperity.Hierarchy(mesh, target_vertices="2%", keep_features="none")
    print(f"{mesh_path.name}: {len(mesh.positions)} vertices, {hierarchy.levels} levels")
    vertices, errors = [], []
    for level in range(hierarchy.levels):
        positions, triangles = hierarchy.level(level)
        error = asperity.hausdorff(mesh, (positions, triangles))
        vertices.append(len(positions))
        errors.append(error)
        print(f"level {level:2}: {len(positions):6} vertices, Hausdorff {100 * error:.3f}% of the diagonal")
    picture = out / "hierarchy_tour.png"
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        write_png(picture, asperity.render(hierarchy.level(0), size=(640, 480)))
        print(f"matplotlib is not installed: {picture} shows the base domain")
        return
    figure, axis = plt.subplots(figsize=(6, 4))
    axis.semilogy(range(hierarchy.levels), [max(e, 1e-7) * 100 for e in errors], marker="o")
    axis.set_xlabel("level (0 = base domain)")
    axis.set_ylabel("Hausdorff distance, % of the diagonal")
    axis.set_title(f"{mesh_path.name}: {vertices[0]} to {vertices[-1]} vertices")
    figure.tight_layout()
    figure.savefig(picture, dpi=100)
    print(f"{picture}: the error per level")


if __name__ == "__main__":
    main()
