"""Shared fixtures: the repository, the shared meshes, the command-line binary, meshes
made in numpy."""

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]


def shared_meshes() -> Path:
    """The shared meshes: ../shared/data/meshes beside the checkout, or where
    scripts/fetch-test-meshes.sh put them. Missing meshes fail, they never skip."""
    for candidate in (REPO.parent / "shared/data/meshes", REPO / "target/test-meshes/data/meshes"):
        if (candidate / "femur.off").is_file():
            return candidate
    pytest.fail(
        f"the shared meshes are missing: expected {REPO.parent / 'shared/data/meshes'} "
        "(run scripts/fetch-test-meshes.sh, as make test does)"
    )


@pytest.fixture(scope="session")
def meshes() -> Path:
    return shared_meshes()


@pytest.fixture(scope="session")
def cli() -> Path:
    """The command-line binary the Python results are compared with ($ASPERITY_CLI, or a
    build in target/). With ASPERITY_NO_CLI set (scripts/python-wheel-check.sh, where the
    system's OpenMesh the binary links is hidden), the tests comparing with it are skipped:
    the same tests ran with it against the same wheel just before."""
    if os.environ.get("ASPERITY_NO_CLI"):
        pytest.skip("the command line cannot run where the system's native libraries are hidden")
    named = os.environ.get("ASPERITY_CLI")
    candidates = [Path(named).resolve()] if named else [REPO / "target/release/asperity", REPO / "target/debug/asperity"]
    for c in candidates:
        if c.is_file():
            return c
    pytest.fail(f"the asperity binary is missing: expected {candidates[0]} (cargo build --release)")


def run_cli(binary: Path, *args: str, cwd: Path) -> str:
    out = subprocess.run([str(binary), *args], cwd=cwd, capture_output=True, text=True)
    assert out.returncode == 0, f"asperity {' '.join(args)}: {out.stderr}"
    return out.stdout


def icosphere(subdivisions: int = 2):
    """A unit icosphere made in numpy: positions (n, 3) float64, triangles (m, 3) int64."""
    t = (1 + 5 ** 0.5) / 2
    positions = [
        (-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
        (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1),
    ]
    faces = [
        (0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
        (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
        (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1),
    ]
    positions = [np.array(p, dtype=float) / np.linalg.norm(p) for p in positions]
    for _ in range(subdivisions):
        midpoints = {}
        refined = []

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in midpoints:
                m = positions[a] + positions[b]
                positions.append(m / np.linalg.norm(m))
                midpoints[key] = len(positions) - 1
            return midpoints[key]

        for a, b, c in faces:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            refined += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = refined
    return np.array(positions), np.array(faces, dtype=np.int64)


def faces_as_set(positions, triangles):
    """Triangles as a set of position triples (independent of vertex order and rotation)."""
    out = set()
    for t in triangles:
        corners = [tuple(positions[v]) for v in t]
        k = corners.index(min(corners))
        out.add(tuple(corners[k:] + corners[:k]))
    return out


def cpp_example_output(prefix, names):
    """The files examples/cpp/integration.cpp wrote as ``prefix.name`` under
    target/cpp-example/out (scripts/cpp-example.sh runs it before these tests in make test),
    by name. A missing file fails, naming where it belongs."""
    out = REPO / "target/cpp-example/out"
    paths = {n: out / f"{prefix}.{n}" for n in names}
    missing = [n for n, path in paths.items() if not path.is_file()]
    if missing:
        pytest.fail(f"the C++ example's output is missing from {out} ({', '.join(missing)}): run scripts/cpp-example.sh")
    return paths


def raw_rows(path):
    """A raw little-endian array of rows of three the C++ example wrote: float64 for
    ``.f64``, uint32 for ``.u32``."""
    dtype = {".f64": "<f8", ".u32": "<u4"}[path.suffix]
    return np.fromfile(path, dtype=dtype).reshape(-1, 3)
