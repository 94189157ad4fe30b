"""asperity from numpy: controllable procedural detail on 3D surfaces.

Meshes are numpy arrays — positions ``(n, 3) float64``, triangles ``(m, 3) uint32`` —
or any object with ``.vertices`` and ``.faces`` (a ``trimesh.Trimesh``), or a
``(positions, triangles)`` pair. Keyword options are the command line's flags with
underscores (``target_vertices="5%"`` is ``--target-vertices 5%``): they are the fields of
the library's request the flags fill too, sent as JSON with no argv between, so
they mean the same and are checked the same, a message naming the keyword
(``swap_weight=-1: must be a non-negative weight``); an unknown one is an
:class:`InputError` listing the options there are. Results are bit for bit the command
line's.

Errors raise :class:`InputError` (a ``ValueError``: a bad file, mesh, recipe or option)
or :class:`InternalError` (a ``RuntimeError``: please report it). Long calls release the
GIL and stop at their next progress report on Ctrl-C (``KeyboardInterrupt``); progress is
printed to stderr only with ``progress=True``. ``progress`` may also be a function
``(stage, done, total)`` called at each report from the call's worker thread (under the
GIL): returning ``False`` stops the call with :class:`Cancelled` (nothing half-made is
left); an exception it raises stops the call and arrives unchanged.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, Iterator, List, Literal, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _asperity as _native
from ._asperity import Cancelled, InputError, InternalError, Level, __version__

__all__ = [
    "Cancelled",
    "InputError",
    "InternalError",
    "Mesh",
    "Hierarchy",
    "Level",
    "read",
    "write",
    "info",
    "repair",
    "analyze",
    "detail",
    "compare",
    "hausdorff",
    "terrain",
    "terrain_mesh",
    "terrain_layers",
    "noise",
    "render",
    "clouds",
    "FEATURE_CLASSES",
    "__version__",
]

#: Names of the feature classes :func:`analyze` returns as ``feature_class`` codes.
FEATURE_CLASSES = ("face", "weak_edge", "strong_edge", "corner")


@dataclass
class Mesh:
    """A triangle mesh: positions ``(n, 3) float64``, triangles ``(m, 3) uint32`` and
    per-vertex attributes by name (``normals`` ``(n, 3)``, ``colors`` ``(n, 3) uint8``,
    scalars ``(n,)``)."""

    positions: np.ndarray
    triangles: np.ndarray
    attributes: Dict[str, np.ndarray] = field(default_factory=dict)
    #: What the reader ignored or merged, one note each.
    notes: List[str] = field(default_factory=list)

    @property
    def vertices(self) -> np.ndarray:
        """The positions, under trimesh's name."""
        return self.positions

    @property
    def faces(self) -> np.ndarray:
        """The triangles, under trimesh's name."""
        return self.triangles

    def __iter__(self) -> Iterator[np.ndarray]:
        """``positions, triangles = mesh``."""
        return iter((self.positions, self.triangles))

    def to_trimesh(self) -> Any:
        """The mesh as a ``trimesh.Trimesh`` (vertices and faces as they are, not merged or
        reordered; ``normals`` and ``colors`` as vertex normals and colours, the other
        attributes in ``vertex_attributes``). Needs trimesh installed."""
        try:
            import trimesh
        except ImportError as missing:
            raise ImportError("Mesh.to_trimesh needs trimesh: pip install trimesh") from missing
        extra = {k: v for k, v in self.attributes.items() if k not in ("normals", "colors")}
        return trimesh.Trimesh(
            vertices=self.positions,
            faces=self.triangles,
            vertex_normals=self.attributes.get("normals"),
            vertex_colors=self.attributes.get("colors"),
            vertex_attributes=extra,
            process=False,
        )


MeshLike = Union[Mesh, Tuple[Any, Any], Any]

#: ``progress=``: False (silent), True (printed to stderr) or a function
#: ``(stage, done, total)``; ``False`` from it cancels the call (:class:`Cancelled`).
Progress = Union[bool, Callable[[str, int, int], Optional[bool]]]


def _arrays(mesh: MeshLike, triangles: Any = None) -> Tuple[np.ndarray, np.ndarray]:
    """Positions as C-contiguous float64 (n, 3) and triangles as uint32 (m, 3)."""
    if triangles is not None:
        positions = mesh
    elif isinstance(mesh, Mesh):
        positions, triangles = mesh.positions, mesh.triangles
    elif hasattr(mesh, "vertices") and hasattr(mesh, "faces"):
        positions, triangles = mesh.vertices, mesh.faces
    elif isinstance(mesh, (tuple, list)) and len(mesh) == 2:
        positions, triangles = mesh
    else:
        raise InputError(
            "a mesh is an asperity.Mesh, an object with .vertices and .faces, or a (positions, triangles) pair"
        )
    positions = np.ascontiguousarray(positions, dtype=np.float64)
    if positions.ndim != 2 or positions.shape[1] != 3:
        raise InputError(f"positions must be an (n, 3) array, not {positions.shape}")
    raw = np.asarray(triangles)
    if raw.size and not np.issubdtype(raw.dtype, np.integer):
        raise InputError(f"triangles must be integers, not {raw.dtype}")
    if raw.ndim != 2 or raw.shape[1] != 3:
        raise InputError(f"triangles must be an (m, 3) array, not {raw.shape}")
    if raw.size and (raw.min() < 0 or raw.max() > 0xFFFFFFFF):
        k = int(np.argmax((raw < 0).any(axis=1) | (raw > 0xFFFFFFFF).any(axis=1)))
        raise InputError(f"triangle {k} names vertex index {raw[k].tolist()} outside 0..2^32-1")
    return positions, np.ascontiguousarray(raw, dtype=np.uint32)


def _fields(options: Mapping[str, Any]) -> str:
    """Keyword options as the JSON object of a library request's fields (numpy scalars
    and arrays as plain values); the library refuses an unknown or mistyped one by name."""

    def plain(value: Any) -> Any:
        if isinstance(value, os.PathLike):
            return os.fspath(value)
        if isinstance(value, np.floating) and value.dtype.itemsize < 8:
            # A float32 as its shortest text (0.7, not 0.699999988…): what the flag would read.
            return plain(float(str(value)))
        if isinstance(value, np.ndarray):
            return plain(value[()]) if value.ndim == 0 else [plain(v) for v in value]
        if isinstance(value, np.generic):
            return plain(value.item())
        if isinstance(value, (list, tuple)):
            return [plain(v) for v in value]
        if isinstance(value, float) and not np.isfinite(value):
            # JSON has no NaN or infinity: a string, which the library names as the wrong type.
            return str(value)
        return value

    return json.dumps({key: plain(value) for key, value in options.items()})


def read(path: Union[str, "os.PathLike[str]"]) -> Mesh:
    """Reads a mesh file (OBJ, PLY, OFF, STL, GLB): positions, triangles (polygons
    triangulated), and the attributes the file holds."""
    positions, triangles, normals, colors, scalars, notes = _native.read(str(path))
    attributes: Dict[str, np.ndarray] = {}
    if normals is not None:
        attributes["normals"] = normals
    if colors is not None:
        attributes["colors"] = colors
    attributes.update(scalars)
    return Mesh(positions, triangles, attributes, list(notes))


def write(
    path: Union[str, "os.PathLike[str]"],
    positions: Any,
    triangles: Any = None,
    *,
    ascii: bool = False,
    **attributes: np.ndarray,
) -> None:
    """Writes a mesh in the format the extension names. ``positions`` may also be a mesh
    (then ``triangles`` is left out and its attributes are written too); attributes:
    ``normals`` (n, 3), ``colors`` (n, 3) uint8, and scalars (n,) by name (PLY keeps them
    all, other formats what they can). ``ascii`` writes text PLY or STL."""
    if triangles is None and isinstance(positions, Mesh):
        attributes = {**positions.attributes, **attributes}
    p, t = _arrays(positions, triangles)
    normals = attributes.pop("normals", None)
    colors = attributes.pop("colors", None)
    if normals is not None:
        normals = np.ascontiguousarray(normals, dtype=np.float64)
    if colors is not None:
        colors = np.ascontiguousarray(colors, dtype=np.uint8)
    scalars = [(name, np.ascontiguousarray(v, dtype=np.float64)) for name, v in attributes.items()]
    _native.write(str(path), p, t, normals, colors, scalars, ascii)


def info(mesh: MeshLike) -> Dict[str, Any]:
    """``asperity info``'s validation report: counts, boundary loops, manifoldness,
    orientation, components, Euler characteristic, genus, degenerate faces."""
    return json.loads(_native.info(*_arrays(mesh)))


def repair(mesh: MeshLike) -> Tuple[Mesh, Dict[str, Any]]:
    """``--repair``: removes degenerate and duplicate faces, splits non-manifold vertices
    and edges, orients faces consistently, drops unreferenced vertices. Returns the
    repaired mesh and what changed."""
    positions, triangles, report = _native.repair(*_arrays(mesh))
    return Mesh(positions, triangles), json.loads(report)


def analyze(mesh: MeshLike, *, repair: bool = False, **options: Any) -> Dict[str, np.ndarray]:
    """``asperity analyze``: vertex ``normals`` (n, 3), ``mean_curvature``,
    ``gaussian_curvature``, ``k1``, ``k2`` (n,), ``feature_class`` (n,) uint8 codes into
    :data:`FEATURE_CLASSES`, and ``diffusion`` directions (n, 3).

    Options: ``normals`` ("angle", "area", "uniform"), ``corner``, ``face``, ``strong``
    (the voting-tensor thresholds, 0 to 1), ``repair``; an unknown one is an
    :class:`InputError` naming it."""
    return _native.analyze(*_arrays(mesh), _fields(options), repair)


class Hierarchy:
    """The feature-sensitive 4-k hierarchy of a mesh (``asperity simplify``), every level
    kept: ``levels`` levels, level 0 the base domain and level ``levels - 1`` the input.

    Options are ``simplify``'s (the library's hierarchy request, as a recipe's
    ``[hierarchy]`` table also gives it), as typed keyword arguments (a misspelt one is a
    ``TypeError``; a bad value an :class:`InputError` naming the keyword):

    - ``target_vertices``: stop at this many vertices (``377``) or this share of the
      input's (``"1%"``); ``levels``: stop after this many levels; ``max_error``: never
      remove a vertex whose error exceeds this share of the bounding-box diagonal.
    - ``keep_features``: the feature vertices kept — ``"none"``, ``"corners"`` (thesis
      Fig. 5.15), ``"strong"`` (the default) or ``"all"``; ``feature_vertices``:
      ``"along-lines"`` (the default: removed along their line) or ``"keep"``.
    - ``removal_weight`` and ``swap_weight``: the weights of E(v) (eq. 4.1).
    - ``intersection_guard``: leave out the clusters whose new faces would cut the
      surface (on by default); ``chunks``: build in this many parts in parallel, their
      borders fenced, then continue on their joined bases (``simplify --chunks``; needs
      ``target_vertices`` or ``max_error``, takes no ``levels``).
    - ``repair``: repair the mesh first (every array stays in the caller's numbering);
      ``progress``: True prints the build's progress to stderr; a function
      ``(stage, done, total)`` watches it, and stops it by returning False.

    What the build made and what stopped it is :attr:`report`."""

    def __init__(
        self,
        positions: MeshLike,
        triangles: Any = None,
        *,
        target_vertices: Union[int, str, None] = "5%",
        levels: Optional[int] = None,
        max_error: Optional[float] = None,
        keep_features: Optional[Literal["none", "corners", "strong", "all"]] = None,
        feature_vertices: Optional[Literal["along-lines", "keep"]] = None,
        removal_weight: float = 0.75,
        swap_weight: float = 0.25,
        intersection_guard: bool = True,
        chunks: Optional[int] = None,
        repair: bool = False,
        progress: Progress = False,
    ) -> None:
        p, t = _arrays(positions, triangles)
        fields = _fields(
            {
                "target_vertices": target_vertices,
                "levels": levels,
                "max_error": max_error,
                "keep_features": keep_features,
                "feature_vertices": feature_vertices,
                "removal_weight": removal_weight,
                "swap_weight": swap_weight,
                "intersection_guard": intersection_guard,
                "chunks": chunks,
            }
        )
        self._native = _native.Hierarchy(p, t, fields, repair, progress)
        self._parametrization: Optional[Tuple[np.ndarray, np.ndarray]] = None
        self._report: Optional[Dict[str, Any]] = None

    @property
    def report(self) -> Dict[str, Any]:
        """The build's report, ``simplify --json``'s fields: ``input_vertices``,
        ``output_vertices`` (the base domain's), faces, ``levels``,
        ``feature_vertices_kept``, ``hausdorff`` (share of the bounding-box diagonal),
        ``min_angle_deg``, ``sliver_share``, ``target`` (``reached``, ``floor_vertices``,
        ``stopped_by`` and what gave way, counted), ``gave_way`` (in words), ``seconds``
        and ``stage_seconds``. Measured on first use."""
        if self._report is None:
            self._report = json.loads(self._native.report())
        return self._report

    @property
    def levels(self) -> int:
        """The number of levels, the base domain and the input included."""
        return self._native.levels

    def level(self, l: int) -> Tuple[np.ndarray, np.ndarray]:
        """Level ``l``'s positions and triangles (0: the base domain; ``levels - 1``: the
        input; negative counts from the input)."""
        positions, triangles, _ = self._native.level(self._index(l))
        return positions, triangles

    def level_vertex_ids(self, l: int) -> np.ndarray:
        """The input vertex id of each of level ``l``'s positions."""
        return self._native.level(self._index(l))[2]

    def _index(self, l: int) -> int:
        return l + self.levels if l < 0 else l

    @property
    def vertex_level(self) -> np.ndarray:
        """The level at which each input vertex appears (0 for the base domain's): the
        level of its removal; -1 for a vertex ``repair=True`` dropped (no face used it).
        Every array is in the caller's numbering, repaired or not."""
        return self._native.vertex_level

    @property
    def base_face(self) -> np.ndarray:
        """For each input vertex, the index of the base face (in ``level(0)``'s triangles)
        its parametrization puts it on; a base vertex's is a face it is a corner of; -1 for
        a vertex on no face."""
        return self._parametrized()[0].copy()

    @property
    def barycentrics(self) -> np.ndarray:
        """Each input vertex's barycentric coordinates on its base face (n, 3), in the
        order of that triangle's corners (a base vertex: 1 at its corner); NaN for a
        vertex on no face."""
        return self._parametrized()[1].copy()

    def _parametrized(self) -> Tuple[np.ndarray, np.ndarray]:
        if self._parametrization is None:
            self._parametrization = self._native.parametrization()
        return self._parametrization

    def refine(
        self,
        region: Any = None,
        base_level: int = 0,
        *,
        op: Optional[Callable[[Level], Any]] = None,
        progress: Progress = False,
    ) -> Mesh:
        """Refines the base domain back to full resolution.

        With ``op`` (keyword only), a function called with each level as a :class:`Level` (the base
        domain first, the input's level last): it may move ``level.positions`` in place (or
        return new positions), and the next level inserts its vertices on the moved surface
        (thesis §4.5.1, the C++ ``Hierarchy::refine(op)``). An exception it raises arrives
        unchanged; Ctrl-C stops between levels.

        With ``region`` (a boolean per input vertex, or input vertex indices): the region
        at the input's resolution, the rest at ``base_level`` (0: the base domain) — the
        command line's ``refine --region``; with ``op`` too, the levels from ``base_level``
        on insert the region's vertices and the removal rings they need.

        Returns a :class:`Mesh` (``positions, triangles = h.refine()`` still unpacks) whose
        ``attributes["ids"]`` is each vertex's input id; the same ids are
        ``refined_ids`` and what the refinement did is ``refine_report``. A region that is
        not booleans or distinct vertex indices in range is an ``InputError``. ``progress``
        as for the build (with ``op``: one report per level)."""
        mask = None if region is None else self._region_mask(region)
        if isinstance(base_level, bool) or not isinstance(base_level, (int, np.integer)):
            raise InputError(f"base_level must be an integer level, not {type(base_level).__name__}")
        if not 0 <= base_level < self.levels:
            raise InputError(f"base_level {base_level}: the hierarchy has levels 0 (the base domain) to {self.levels - 1}")
        if mask is None and base_level != 0:
            raise InputError("base_level applies to a region refinement: give region= too")
        if op is None:
            positions, triangles, ids, report = self._native.refine(mask, int(base_level), progress)
        else:
            if not callable(op):
                raise InputError(f"op must be a function of a Level, not {type(op).__name__}")

            def step(level: Level) -> None:
                moved = op(level)
                if moved is not None:
                    level.positions = moved
                level.positions = np.ascontiguousarray(level.positions, dtype=np.float64)

            positions, triangles, ids, report = self._native.refine_with(step, mask, int(base_level), progress)
        self.refined_ids: np.ndarray = ids
        self.refine_report: Dict[str, Any] = json.loads(report)
        return Mesh(positions, triangles, {"ids": ids})

    def _region_mask(self, region: Any) -> np.ndarray:
        n = self._native.input_vertices
        values = np.asarray(region)
        if values.size == 0:
            return np.zeros(n, dtype=np.bool_)
        if values.ndim != 1:
            raise InputError(f"region must be one-dimensional, not of shape {values.shape}")
        if values.dtype == np.bool_:
            if len(values) != n:
                raise InputError(f"region has {len(values)} booleans for {n} vertices")
            return np.ascontiguousarray(values)
        if not np.issubdtype(values.dtype, np.integer):
            raise InputError(f"region must be booleans (one per vertex) or vertex indices, not {values.dtype}")
        bad = np.nonzero((values < 0) | (values >= n))[0]
        if len(bad):
            raise InputError(f"region: index {values[bad[0]]} (at {bad[0]}) is not a vertex (0 to {n - 1})")
        unique, counts = np.unique(values, return_counts=True)
        if (counts > 1).any():
            raise InputError(
                f"region repeats vertex {unique[counts > 1][0]}: vertex indices are distinct "
                "(for a 0/1 mask, pass booleans: region.astype(bool))"
            )
        mask = np.zeros(n, dtype=np.bool_)
        mask[values] = True
        return mask

    @property
    def stages(self) -> Dict[str, float]:
        """Build time by stage, seconds."""
        return json.loads(self._native.stages())


def _recipe_text(recipe: Union[str, Mapping[str, Any], None]) -> Tuple[str, bool]:
    if recipe is None:
        return "", False
    if isinstance(recipe, str):
        return recipe, False
    return json.dumps(recipe), True


def detail(
    mesh: MeshLike,
    recipe: Union[str, Mapping[str, Any], None] = None,
    *,
    allow_self_intersections: bool = False,
    repair: bool = False,
    progress: Progress = False,
    **hierarchy: Any,
) -> Tuple[Mesh, Dict[str, Any]]:
    """``asperity detail``: builds the hierarchy, applies the recipe's steps at their
    levels and refines back to full resolution. ``recipe`` is a recipe's TOML text or the
    same as a dict (``{"seed": 3, "step": [{"op": "noise", ...}]}``); without one this is
    the round trip. ``allow_self_intersections`` keeps the recipe's displacements where
    the result cuts itself (by default they are damped); ``repair`` repairs the mesh
    first. The other keywords are :class:`Hierarchy`'s (``target_vertices``, ``levels``,
    ``max_error``, ``keep_features``, ``feature_vertices``, ``removal_weight``,
    ``swap_weight``, ``intersection_guard``, ``chunks``): each replaces the recipe's ``[hierarchy]``
    key of its name; an unknown one is an :class:`InputError` naming it. Returns the mesh
    (with ``attributes["colors"]`` when the recipe has a ``[color]`` table) and the
    report."""
    text, is_json = _recipe_text(recipe)
    positions, triangles, colors, report = _native.detail(
        *_arrays(mesh), text, is_json, _fields(hierarchy), allow_self_intersections, repair, progress
    )
    attributes = {} if colors is None else {"colors": colors}
    return Mesh(positions, triangles, attributes), json.loads(report)


def compare(
    mesh: MeshLike,
    *,
    target_vertices: Union[int, str] = "1%",
    methods: Optional[Sequence[str]] = None,
    repair: bool = False,
    progress: Progress = False,
    **options: Any,
) -> Dict[str, Any]:
    """``asperity compare``: ours against OpenMesh, CGAL and meshoptimizer, as the
    command's ``--json`` report: ``at_target`` (one dict per method asked for the target,
    so a method that stops short shows it: Hausdorff and RMS distance as shares of the
    bounding-box diagonal, minimum angles, slivers, time; ours also ``gave_way`` and
    ``stopped_by``) and ``at_common_count`` (``None``, or ``vertices`` and ``rows``: every
    method again at the smallest count all reached, when the counts differ). ``methods``
    names any of "asperity", "openmesh", "cgal", "meshoptimizer" (all by default); other
    options: ``keep_features`` and ``feature_vertices`` (ours, as :class:`Hierarchy`'s),
    ``repair``."""
    if isinstance(methods, str):
        methods = methods.split(",")  # "asperity,cgal", as the command line's --methods
    fields = _fields({"target_vertices": target_vertices, "methods": methods, **options})
    return json.loads(_native.compare(*_arrays(mesh), fields, repair, progress))


def hausdorff(reference: MeshLike, other: MeshLike) -> float:
    """The symmetric Hausdorff distance between two meshes (by CGAL), as a share of the
    reference's bounding-box diagonal — what ``simplify`` and ``compare`` report."""
    return _native.hausdorff(*_arrays(reference), *_arrays(other))


def terrain(*, progress: Progress = False, **options: Any) -> np.ndarray:
    """``asperity terrain``'s heights as a (rows, columns) float64 array: ``size``,
    ``method`` ("classic", "smooth"), ``hurst``, ``seed``, ``sea_level``, ``erode``
    ("thermal", "hydraulic", "thermal,hydraulic") with ``rain``, ``capacity``…,
    ``tile=(i, j)`` with ``tile_size``, ``preset``… (every field of the library's terrain
    request, as the command line's flags name them; a misspelt one is refused by name)."""
    return _native.terrain(_fields(options), progress)


def terrain_layers(*, progress: Progress = False, **options: Any) -> Dict[str, np.ndarray]:
    """The heights of ``terrain(erode="hydraulic", …)`` and the hydraulic erosion's layers
    from the same run, as (rows, columns) float64 arrays keyed ``"heights"``, ``"flow"``,
    ``"sediment"``, ``"water"``, ``"wetness"``: masks in [0, 1] (``layers="flow,water"``
    picks some; all four by default). The same keyword arguments as ``terrain``."""
    heights, layers = _native.terrain_layers(_fields(options), progress)
    return {"heights": heights, **dict(layers)}


def terrain_mesh(**options: Any) -> Mesh:
    """``asperity terrain``'s mesh, as it writes ``.ply``: a heightfield's grid (or a
    ``tile``) with normals and height colours, or with ``method="dual"`` Janeczek's surface
    over the quadrilateral ``x``, ``y`` (``levels``, ``deterministic``, ``cross_product``,
    ``no_mean_correction``)."""
    positions, triangles, normals, colors = _native.terrain_mesh(_fields(options))
    attributes = {}
    if normals is not None:
        attributes["normals"] = normals
    if colors is not None:
        attributes["colors"] = colors
    return Mesh(positions, triangles, attributes)


def noise(kind: str, points: Any, **params: Any) -> np.ndarray:
    """``asperity noise``'s field at given points: (n, 2) points sample the plane as the
    images do, (n, 3) points sample space (Gabor and phasor kernels oriented in the global
    frame). ``params`` are the flags of the kind (``octaves``, ``k``, ``f0``, ``seed``…)."""
    pts = np.ascontiguousarray(points, dtype=np.float64)
    if pts.ndim != 2:
        raise InputError(f"points must be an (n, 2) or (n, 3) array, not {pts.shape}")
    return _native.noise(pts, _fields({"kind": kind, **params}))


def render(mesh: MeshLike, *, repair: bool = False, **options: Any) -> np.ndarray:
    """``asperity render``'s picture as a (height, width, 4) uint8 RGBA array. Options
    (``render``'s flags): ``size=(w, h)``, ``mode`` ("faces", "wireframe", "points"),
    ``yaw`` and ``pitch`` (degrees), ``up`` ("x", "y", "z"), ``colors`` ("attribute",
    "height", "none", "scalar:NAME"), ``background`` ("#rrggbb" or "transparent"),
    ``samples``, ``crease``, ``edges``, ``water_level``, ``water_clarity``, ``texture`` (a
    PNG's path), ``repair``; an unknown one is an :class:`InputError` naming it."""
    return _native.render(*_arrays(mesh), _fields(options), repair)


def clouds(**options: Any) -> Tuple[np.ndarray, float]:
    """``asperity clouds``: a (size, size, 3) uint8 RGB sky and its cloud cover (0–1).
    Options: ``size`` (pixels per side, 2^n + 1), ``hurst``, ``seed``, ``threshold`` (0–1),
    ``sky`` and ``cloud`` (R, G, B); an unknown one is an :class:`InputError` naming it."""
    return _native.clouds(_fields(options))
