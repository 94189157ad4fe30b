#!/usr/bin/env python3
"""Helper of scripts/fetch-corpus.sh: converts CAD and mesh files into PLY and computes
the manifest's statistics the way asperity's readers and `validate` see a file.

    corpus_mesh.py tessellate SRC.step|.stp|.iges|.igs|.brep DST.ply [SIZE]
        gmsh (PyPI wheel, built with OpenCASCADE) meshes the CAD surfaces; SIZE is the
        target edge length as a fraction of the bounding-box diagonal (default 0.02).
    corpus_mesh.py convert SRC DST.ply
        Any file the readers below take (or VRML 2 IndexedFaceSets) to binary PLY; faces
        of fewer than 3 corners, which asperity's readers refuse, are dropped.
    corpus_mesh.py stats FILE
        One tab-separated line: vertices faces components boundary_loops genus
        min_angle_deg notes.

Reader semantics follow src/io: every OBJ `v` line is a vertex; polygons are split into
triangles
(asperity's ear clipping, ported); faces that repeat a corner are dropped; STL corners with bit-identical coordinates are
welded. Topology follows src/mesh/validate.rs: components are connected through shared
vertices, boundary loops are walked along boundary edges as undirected edges, and the
genus (2c - b - chi) / 2 is given only for an orientable, edge- and vertex-manifold mesh.
"""

import math
import re
import struct
import sys

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components


# ---------------------------------------------------------------- reading

class Mesh:
    def __init__(self, positions, polygons):
        self.positions = np.asarray(positions, dtype=np.float64).reshape(-1, 3)
        self.notes = []
        tris, polys, dropped, self.short = triangulate(self.positions, polygons)
        self.triangles = tris
        if self.short:
            self.notes.append(f"{self.short} faces of fewer than 3 corners dropped")
        if polys:
            self.notes.append(f"{polys} polygons split into triangles")
        if dropped:
            self.notes.append(f"{dropped} faces repeating a vertex dropped")


def clean_polygon(p):
    """src/io/mod.rs without_repeated_corners: None when no face is left."""
    q = [v for i, v in enumerate(p) if i == 0 or v != p[i - 1]]
    while len(q) > 1 and q[0] == q[-1]:
        q.pop()
    if len(q) < 3 or len(set(q)) != len(q):
        return None
    return q


MAX_EAR_CLIPPED = 256


def project_to_plane(positions, polygon):
    """src/mesh/triangulate.rs project_to_plane: drop the Newell normal's dominant axis."""
    pts = [positions[v] for v in polygon]
    nx = ny = nz = 0.0
    for i, p in enumerate(pts):
        q = pts[(i + 1) % len(pts)]
        nx += (p[1] - q[1]) * (p[2] + q[2])
        ny += (p[2] - q[2]) * (p[0] + q[0])
        nz += (p[0] - q[0]) * (p[1] + q[1])
    ax, ay, az = abs(nx), abs(ny), abs(nz)
    if ax >= ay and ax >= az:
        u, v, sign = 1, 2, math.copysign(1.0, nx)
    elif ay >= az:
        u, v, sign = 2, 0, math.copysign(1.0, ny)
    else:
        u, v, sign = 0, 1, math.copysign(1.0, nz)
    return [(sign * p[u], p[v]) for p in pts]


def cross2(o, a, b):
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def find_ear(flat, ring):
    m = len(ring)
    for i in range(m):
        a, b, c = flat[ring[(i + m - 1) % m]], flat[ring[i]], flat[ring[(i + 1) % m]]
        if cross2(a, b, c) <= 0.0:
            continue
        ok = True
        for j, r in enumerate(ring):
            if j == i or j == (i + m - 1) % m or j == (i + 1) % m:
                continue
            p = flat[r]
            if cross2(a, b, p) >= 0.0 and cross2(b, c, p) >= 0.0 and cross2(c, a, p) >= 0.0:
                ok = False
                break
        if ok:
            return i
    return None


def triangulate_polygon(positions, polygon, out):
    """src/mesh/triangulate.rs triangulate_polygon: ear clipping, fans past 256 corners."""
    n = len(polygon)
    if n == 3 or n > MAX_EAR_CLIPPED:
        out.extend((polygon[0], polygon[k], polygon[k + 1]) for k in range(1, n - 1))
        return
    flat = project_to_plane(positions, polygon)
    ring = list(range(n))
    while len(ring) > 3:
        i = find_ear(flat, ring)
        if i is None:
            break
        m = len(ring)
        out.append((polygon[ring[(i + m - 1) % m]], polygon[ring[i]], polygon[ring[(i + 1) % m]]))
        ring.pop(i)
    rest = [polygon[i] for i in ring]
    out.extend((rest[0], rest[k], rest[k + 1]) for k in range(1, len(rest) - 1))


def triangulate(positions, polygons):
    """polygons: an (m, 3) int array, or a list of index lists."""
    if isinstance(polygons, np.ndarray):
        t = polygons.astype(np.int64).reshape(-1, 3)
        keep = (t[:, 0] != t[:, 1]) & (t[:, 1] != t[:, 2]) & (t[:, 0] != t[:, 2])
        return t[keep], 0, int((~keep).sum()), 0
    out, split, dropped, short = [], 0, 0, 0
    pos = None
    for p in polygons:
        if len(p) < 3:
            short += 1
            continue
        if len(p) == 3:
            if p[0] != p[1] and p[1] != p[2] and p[0] != p[2]:
                out.append(p)
            else:
                dropped += 1
            continue
        q = clean_polygon(list(p))
        if q is None:
            dropped += 1
            continue
        if len(q) > 3:
            split += 1
            if pos is None:
                pos = positions.tolist()
        triangulate_polygon(pos, q, out)
    return np.array(out, dtype=np.int64).reshape(-1, 3), split, dropped, short


def read_off(path):
    text = open(path, "rb").read().decode("latin-1")
    lines = []
    for line in text.splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            lines.append(line)
    head = lines[0].split()
    if not head[0].endswith("OFF"):
        raise ValueError(f"{path}: not an OFF file")
    rest = head[1:]
    i = 1
    if not rest:
        rest = lines[1].split()
        i = 2
    nv, nf = int(rest[0]), int(rest[1])
    pos = np.array([[float(x) for x in lines[i + k].split()[:3]] for k in range(nv)], dtype=np.float64)
    polys = []
    for k in range(nf):
        tok = lines[i + nv + k].split()
        n = int(tok[0])
        polys.append(tuple(int(x) for x in tok[1:1 + n]))
    return Mesh(pos, polys)


def read_obj(path):
    text = open(path, "rb").read().decode("utf-8", errors="replace").replace("\\\n", " ")
    pos, polys = [], []
    for line in text.splitlines():
        tok = line.split()
        if not tok:
            continue
        if tok[0] == "v":
            pos.append((float(tok[1]), float(tok[2]), float(tok[3])))
        elif tok[0] == "f":
            n = len(pos)
            face = []
            for c in tok[1:]:
                i = int(c.split("/")[0])
                face.append(i - 1 if i > 0 else n + i)
            polys.append(tuple(face))
    return Mesh(pos, polys)


PLY_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
    "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
    "float": "f4", "float32": "f4", "double": "f8", "float64": "f8",
}


def read_ply(path):
    data = open(path, "rb").read()
    end = data.index(b"end_header")
    end = data.index(b"\n", end) + 1
    header = data[:end].decode("latin-1").splitlines()
    fmt, elements = None, []
    for line in header:
        tok = line.split()
        if not tok:
            continue
        if tok[0] == "format":
            fmt = tok[1]
        elif tok[0] == "element":
            elements.append([tok[1], int(tok[2]), []])
        elif tok[0] == "property":
            if tok[1] == "list":
                elements[-1][2].append((tok[4], "list", PLY_TYPES[tok[2]], PLY_TYPES[tok[3]]))
            else:
                elements[-1][2].append((tok[2], PLY_TYPES[tok[1]]))
    pos, polys = None, None
    if fmt == "ascii":
        tokens = data[end:].split()
        at = 0
        for name, count, props in elements:
            rows = []
            for _ in range(count):
                row = {}
                for p in props:
                    if len(p) == 4:
                        n = int(tokens[at]); at += 1
                        row[p[0]] = [int(float(t)) for t in tokens[at:at + n]]; at += n
                    else:
                        row[p[0]] = float(tokens[at]); at += 1
                rows.append(row)
            if name == "vertex":
                pos = np.array([[r["x"], r["y"], r["z"]] for r in rows], dtype=np.float64)
            elif name == "face":
                key = "vertex_indices" if count and "vertex_indices" in rows[0] else "vertex_index"
                polys = [tuple(r[key]) for r in rows]
    else:
        bo = "<" if fmt == "binary_little_endian" else ">"
        at = end
        for name, count, props in elements:
            if all(len(p) == 2 for p in props):
                dt = np.dtype([(p[0], bo + p[1]) for p in props])
                arr = np.frombuffer(data, dtype=dt, count=count, offset=at)
                at += dt.itemsize * count
                if name == "vertex":
                    pos = np.stack([arr["x"], arr["y"], arr["z"]], axis=1).astype(np.float64)
                continue
            # An element with lists: a fast path for "one list, all triangles", else a loop.
            if len(props) == 1 and len(props[0]) == 4:
                ct, it = np.dtype(bo + props[0][2]), np.dtype(bo + props[0][3])
                dt = np.dtype([("n", ct), ("i", it, (3,))])
                if at + dt.itemsize * count <= len(data):
                    arr = np.frombuffer(data, dtype=dt, count=count, offset=at)
                    if (arr["n"] == 3).all():
                        at += dt.itemsize * count
                        if name == "face":
                            polys = arr["i"].astype(np.int64)
                        continue
            rows = []
            for _ in range(count):
                row = {}
                for p in props:
                    if len(p) == 4:
                        ct, it = np.dtype(bo + p[2]), np.dtype(bo + p[3])
                        n = int(np.frombuffer(data, ct, 1, at)[0]); at += ct.itemsize
                        row[p[0]] = tuple(int(x) for x in np.frombuffer(data, it, n, at)); at += it.itemsize * n
                    else:
                        t = np.dtype(bo + p[1])
                        row[p[0]] = np.frombuffer(data, t, 1, at)[0]; at += t.itemsize
                rows.append(row)
            if name == "face":
                key = "vertex_indices" if count and "vertex_indices" in rows[0] else "vertex_index"
                polys = [r[key] for r in rows]
    if polys is None:
        polys = []
    return Mesh(pos, polys)


def weld(corners):
    """Bit-identical corners to shared vertices (-0.0 as 0.0), in order of first use."""
    c = corners.reshape(-1, 3) + 0.0
    keys = np.ascontiguousarray(c).view(np.dtype((np.void, 24))).ravel()
    _, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
    order = np.argsort(first)
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    return c[first[order]], rank[inverse].reshape(-1, 3)


def read_stl(path):
    data = open(path, "rb").read()
    if len(data) >= 84:
        n = struct.unpack_from("<I", data, 80)[0]
        if 84 + 50 * n == len(data):
            dt = np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
            arr = np.frombuffer(data, dtype=dt, count=n, offset=84)
            pos, tri = weld(arr["v"].astype(np.float64))
            m = Mesh(pos, tri)
            m.notes.insert(0, f"binary STL, {3 * n - len(pos)} corners welded")
            return m
    text = data.decode("utf-8")
    if not text.lstrip("\ufeff").lstrip().startswith("solid"):
        raise ValueError(f"{path}: not an STL file")
    nums = re.findall(r"^\s*vertex\s+(\S+)\s+(\S+)\s+(\S+)", text, flags=re.M)
    corners = np.array(nums, dtype=np.float64)
    pos, tri = weld(corners)
    m = Mesh(pos, tri)
    m.notes.insert(0, f"ASCII STL, {len(corners) - len(pos)} corners welded")
    return m


def read_vrml(path):
    """VRML 2 IndexedFaceSets (coordIndex lists ended by -1) placed by the Transform nodes
    above them (translation, rotation, scale; no DEF/USE, no TextureCoordinate). Each
    set keeps its own vertices, as in the file: a set is one part of an assembly."""
    text = open(path, "rb").read().decode("latin-1")
    text = re.sub(r"#[^\n]*", "", text)
    tokens = re.findall(r"[{}\[\]]|[^\s{}\[\],]+", text)

    def axis_angle(x, y, z, a):
        v = np.array([x, y, z], dtype=np.float64)
        v /= np.linalg.norm(v) or 1.0
        k = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
        m = np.eye(4)
        m[:3, :3] = np.eye(3) + np.sin(a) * k + (1 - np.cos(a)) * (k @ k)
        return m

    pos_all, polys = [], []
    base = 0
    current, saved, blocks = np.eye(4), [], []
    coord, index = None, None
    i, n = 0, len(tokens)
    while i < n:
        t = tokens[i]
        if t == "Transform" and i + 1 < n and tokens[i + 1] == "{":
            j = i + 2
            m = np.eye(4)
            tr, rot, sc = np.zeros(3), None, np.ones(3)
            while j < n and tokens[j] not in ("children", "}"):
                if tokens[j] == "translation":
                    tr = np.array([float(x) for x in tokens[j + 1:j + 4]]); j += 4
                elif tokens[j] == "rotation":
                    rot = [float(x) for x in tokens[j + 1:j + 5]]; j += 5
                elif tokens[j] == "scale":
                    sc = np.array([float(x) for x in tokens[j + 1:j + 4]]); j += 4
                else:
                    j += 1
            m[:3, 3] = tr
            if rot is not None:
                m = m @ axis_angle(*rot)
            m = m @ np.diag([sc[0], sc[1], sc[2], 1.0])
            saved.append(current)
            current = current @ m
            blocks.append("Transform")
            i = j
            continue
        if t == "{":
            blocks.append("")
        elif t == "}":
            if blocks and blocks.pop() == "Transform":
                current = saved.pop()
        elif t in ("point", "coordIndex") and i + 1 < n and tokens[i + 1] == "[":
            j = tokens.index("]", i + 2)
            if t == "point":
                vals = np.array([float(x) for x in tokens[i + 2:j]], dtype=np.float64).reshape(-1, 3)
                coord = (np.c_[vals, np.ones(len(vals))] @ current.T)[:, :3]
            else:
                index = [int(x) for x in tokens[i + 2:j]]
            if coord is not None and index is not None:
                face = []
                for v in index + [-1]:
                    if v < 0:
                        if face:
                            polys.append(tuple(base + f for f in face))
                        face = []
                    else:
                        face.append(v)
                pos_all.append(coord)
                base += len(coord)
                coord, index = None, None
            i = j
        i += 1
    pos = np.concatenate(pos_all) if pos_all else np.zeros((0, 3))
    return Mesh(pos, polys)


def read_any(path, lenient=False):
    """Reads a mesh; a face of fewer than 3 corners is an error, as in asperity's
    readers, unless `lenient` (then it is dropped with a note)."""
    mesh = read_by_extension(path)
    if mesh.short and not lenient:
        raise ValueError(f"{path}: {mesh.short} faces have fewer than 3 corners (asperity refuses the file)")
    return mesh


def read_by_extension(path):
    low = path.lower()
    if low.endswith(".off"):
        return read_off(path)
    if low.endswith(".obj"):
        return read_obj(path)
    if low.endswith(".ply"):
        return read_ply(path)
    if low.endswith(".stl"):
        return read_stl(path)
    if low.endswith(".wrl"):
        return read_vrml(path)
    raise ValueError(f"{path}: no reader for this extension")


def write_ply(mesh, path):
    pos, tri = mesh.positions, mesh.triangles
    with open(path, "wb") as f:
        f.write(
            (
                "ply\nformat binary_little_endian 1.0\ncomment made by asperity scripts/corpus_mesh.py\n"
                f"element vertex {len(pos)}\nproperty double x\nproperty double y\nproperty double z\n"
                f"element face {len(tri)}\nproperty list uchar int vertex_indices\nend_header\n"
            ).encode()
        )
        f.write(np.ascontiguousarray(pos, dtype="<f8").tobytes())
        rec = np.zeros(len(tri), dtype=np.dtype([("n", "u1"), ("i", "<i4", (3,))]))
        rec["n"] = 3
        rec["i"] = tri
        f.write(rec.tobytes())


# ---------------------------------------------------------------- tessellation (gmsh)

def tessellate(src, dst, size=0.02):
    """Meshes the faces of a STEP, IGES or BREP file with gmsh; shared edges of one solid
    give shared vertices, separate solids stay separate components. Tries gmsh's
    Frontal-Delaunay, then MeshAdapt, then Delaunay where a face fails."""
    import gmsh

    last = None
    for algorithm in (6, 1, 5):
        gmsh.initialize(["-noenv"], readConfigFiles=False)
        try:
            gmsh.option.setNumber("General.Terminal", 0)
            gmsh.option.setNumber("General.NumThreads", 1)
            gmsh.model.occ.importShapes(src)
            gmsh.model.occ.synchronize()
            box = gmsh.model.getBoundingBox(-1, -1)
            diag = float(np.linalg.norm(np.array(box[3:]) - np.array(box[:3])))
            gmsh.option.setNumber("Mesh.MeshSizeMax", size * diag)
            gmsh.option.setNumber("Mesh.MeshSizeMin", size * diag / 50)
            gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 12)
            gmsh.option.setNumber("Mesh.Algorithm", algorithm)
            gmsh.model.mesh.generate(2)
            tags, coords, _ = gmsh.model.mesh.getNodes()
            pos = coords.reshape(-1, 3)
            lookup = np.zeros(int(tags.max()) + 1, dtype=np.int64)
            lookup[tags.astype(np.int64)] = np.arange(len(tags))
            tris = []
            for dim, tag in gmsh.model.getEntities(2):
                types, _, nodes = gmsh.model.mesh.getElements(dim, tag)
                for ty, nd in zip(types, nodes):
                    if ty == 2:
                        tris.append(lookup[nd.astype(np.int64)].reshape(-1, 3))
            tri = np.concatenate(tris) if tris else np.zeros((0, 3), dtype=np.int64)
            break
        except Exception as e:  # gmsh raises a bare Exception with its last error
            last = e
            tri = None
        finally:
            gmsh.finalize()
    if tri is None:
        raise SystemExit(f"gmsh could not mesh {src}: {last}")
    used = np.unique(tri)
    remap = np.full(len(pos), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    write_ply(Mesh(pos[used], remap[tri]), dst)


# ---------------------------------------------------------------- statistics

def stats(mesh):
    pos, tri = mesh.positions, mesh.triangles
    nv, nf = len(pos), len(tri)
    notes = list(mesh.notes)
    # Half-edges, sorted by undirected edge then face (src/mesh/validate.rs EdgeTable).
    a = tri.reshape(-1)
    b = tri[:, [1, 2, 0]].reshape(-1)
    face = np.repeat(np.arange(nf), 3)
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    fwd = a < b
    order = np.lexsort((face, hi, lo))
    lo, hi, face, fwd = lo[order], hi[order], face[order], fwd[order]
    new = np.ones(len(lo), dtype=bool)
    new[1:] = (lo[1:] != lo[:-1]) | (hi[1:] != hi[:-1])
    starts = np.flatnonzero(new)
    counts = np.diff(np.append(starts, len(lo)))
    n_edges = len(starts)
    boundary = starts[counts == 1]
    two = starts[counts == 2]
    inconsistent = int((fwd[two] == fwd[two + 1]).sum())
    nm_edges = int((counts > 2).sum())

    # Boundary loops, walked exactly as count_boundary_loops does.
    blo, bhi = lo[boundary].tolist(), hi[boundary].tolist()
    ends = sorted([(v, k) for k, v in enumerate(blo)] + [(v, k) for k, v in enumerate(bhi)])
    at = {}
    for v, k in ends:
        at.setdefault(v, []).append(k)
    used = [False] * len(blo)
    loops = 0
    for first in range(len(blo)):
        if used[first]:
            continue
        used[first] = True
        origin, vertex = blo[first], bhi[first]
        while vertex != origin:
            nxt = next((k for k in at.get(vertex, ()) if not used[k]), None)
            if nxt is None:
                break
            used[nxt] = True
            vertex = bhi[nxt] if blo[nxt] == vertex else blo[nxt]
        loops += 1

    # Non-manifold vertices: corners joined across each edge's faces; a vertex whose
    # corners fall in more than one group has more than one fan.
    group = np.repeat(np.arange(n_edges), counts)
    first_of = starts[group]
    rest = np.flatnonzero(~new)
    def corner(f, v):
        t = tri[f]
        k = np.argmax(t == v[:, None], axis=1)
        return 3 * f + k
    if len(rest):
        c0lo = corner(face[first_of[rest]], lo[rest])
        c1lo = corner(face[rest], lo[rest])
        c0hi = corner(face[first_of[rest]], hi[rest])
        c1hi = corner(face[rest], hi[rest])
        r = np.concatenate([c0lo, c0hi])
        c = np.concatenate([c1lo, c1hi])
    else:
        r = c = np.zeros(0, dtype=np.int64)
    g = coo_matrix((np.ones(len(r)), (r, c)), shape=(3 * nf, 3 * nf))
    _, label = connected_components(g, directed=False)
    pairs = np.unique(np.stack([tri.reshape(-1), label]), axis=1)
    per_vertex = np.bincount(pairs[0], minlength=nv)
    nm_vertices = int((per_vertex > 1).sum())

    # Orientability: faces with a sign, the sign flipping across an inconsistent edge.
    f0, f1 = face[two], face[two + 1]
    flip = fwd[two] == fwd[two + 1]
    src = np.concatenate([f0, f0 + nf])
    dst = np.concatenate([np.where(flip, f1 + nf, f1), np.where(flip, f1, f1 + nf)])
    g = coo_matrix((np.ones(len(src)), (src, dst)), shape=(2 * nf, 2 * nf))
    _, label = connected_components(g, directed=False)
    orientable = bool((label[:nf] != label[nf:]).all())

    # Components: vertices joined through faces, counted over referenced vertices.
    referenced = np.zeros(nv, dtype=bool)
    referenced[tri.reshape(-1)] = True
    r = np.concatenate([tri[:, 0], tri[:, 1]])
    c = np.concatenate([tri[:, 1], tri[:, 2]])
    g = coo_matrix((np.ones(len(r)), (r, c)), shape=(nv, nv))
    _, label = connected_components(g, directed=False)
    components = len(np.unique(label[referenced]))
    chi = int(referenced.sum()) - n_edges + nf
    genus = "-"
    if nm_edges == 0 and nm_vertices == 0 and orientable:
        twice = 2 * components - loops - chi
        if twice % 2 == 0 and twice >= 0:
            genus = str(twice // 2)

    # Angles, and degenerate faces as is_degenerate_triangle sees them.
    p = pos[tri]
    e0, e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 1], p[:, 0] - p[:, 2]
    l0, l1, l2 = (np.linalg.norm(e, axis=1) for e in (e0, e1, e2))
    with np.errstate(invalid="ignore", divide="ignore"):
        ang = np.stack([
            np.arccos(np.clip(-(e2 * e0).sum(1) / (l2 * l0), -1, 1)),
            np.arccos(np.clip(-(e0 * e1).sum(1) / (l0 * l1), -1, 1)),
            np.arccos(np.clip(-(e1 * e2).sum(1) / (l1 * l2), -1, 1)),
        ], axis=1)
    ang = np.degrees(np.nan_to_num(ang, nan=0.0))
    min_face = ang.min(axis=1) if nf else np.zeros(0)
    min_angle = float(min_face.min()) if nf else 0.0
    scale = np.max(np.abs(np.concatenate([e0, e2, e1], axis=1)), axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        s = np.where(scale > 0, scale, 1.0)[:, None]
        ab, ac, bc = e0 / s, -e2 / s, e1 / s
        longest = np.max(np.stack([(ab * ab).sum(1), (bc * bc).sum(1), (ac * ac).sum(1)]), axis=0)
        degenerate = (scale == 0) | (np.linalg.norm(np.cross(ab, ac), axis=1) <= 1e-12 * longest)
    n_degenerate = int(degenerate.sum())

    if nm_edges or nm_vertices:
        notes.append(f"non-manifold: {nm_edges} edges, {nm_vertices} vertices")
    if not orientable:
        notes.append("not orientable")
    elif inconsistent:
        notes.append(f"{inconsistent} inconsistently oriented edges")
    if n_degenerate:
        notes.append(f"{n_degenerate} degenerate faces")
    unref = nv - int(referenced.sum())
    if unref:
        notes.append(f"{unref} unreferenced vertices")
    if nf:
        notes.append(f"{100.0 * (min_face < 5.0).mean():.1f}% of faces with an angle < 5 deg")
    return {
        "vertices": nv, "faces": nf, "components": components, "boundary_loops": loops,
        "genus": genus, "min_angle_deg": f"{min_angle:.3f}", "notes": "; ".join(notes),
    }


def main(argv):
    cmd = argv[1]
    if cmd == "tessellate":
        tessellate(argv[2], argv[3], float(argv[4]) if len(argv) > 4 else 0.02)
    elif cmd == "convert":
        mesh = read_any(argv[2], lenient=True)
        write_ply(mesh, argv[3])
        print("; ".join(mesh.notes) or "no changes")
    elif cmd == "stats":
        s = stats(read_any(argv[2]))
        print("\t".join(str(s[k]) for k in
                        ("vertices", "faces", "components", "boundary_loops", "genus", "min_angle_deg", "notes")))
    else:
        raise SystemExit(f"unknown command {cmd}")


if __name__ == "__main__":
    main(sys.argv)
