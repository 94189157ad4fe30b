"""Refinement with a Python operator at every level (#39): the level view, moved surfaces,
exceptions, regions; the build report, typed options and trimesh objects."""

import json

import numpy as np
import pytest

import asperity
from conftest import cpp_example_output, faces_as_set, icosphere, raw_rows, run_cli


@pytest.fixture(scope="module")
def sphere():
    positions, triangles = icosphere(4)
    return positions, triangles, asperity.Hierarchy(positions, triangles, target_vertices="5%")


def test_the_operator_sees_every_level_as_the_hierarchy_holds_it(sphere):
    positions, triangles, h = sphere
    seen = []

    def look(level):
        seen.append(level.level)
        assert level.level_count == h.levels
        ids = level.ids
        assert len(level) == len(ids) == len(level.positions)
        assert set(ids.tolist()) == set(h.level_vertex_ids(level.level).tolist())
        np.testing.assert_array_equal(level.positions, positions[ids])
        assert level.faces.shape[1] == 3 and level.faces.max() < len(ids)
        np.testing.assert_allclose(np.linalg.norm(level.normals, axis=1), 1.0, atol=1e-12)
        # On a unit sphere the vertex normals point outwards.
        assert (np.einsum("ij,ij->i", level.normals, level.positions) > 0.9).all()
        np.testing.assert_array_equal(level.vertex_levels, h.vertex_level[ids])

    refined = h.refine(op=look)
    assert seen == list(range(h.levels))
    # An operator that moves nothing gives back the input exactly.
    assert faces_as_set(*refined) == faces_as_set(positions, triangles)
    np.testing.assert_array_equal(refined.attributes["ids"], h.refined_ids)
    np.testing.assert_array_equal(refined.positions, positions[h.refined_ids])
    assert h.refine_report["levels"] == h.levels - 1 and h.refine_report["inserted"] == len(positions) - len(h.level(0)[0])


def test_a_move_at_a_coarse_level_carries_the_finer_vertices_with_it(sphere):
    positions, triangles, h = sphere
    lifted = {}

    def lift(level):
        if level.level == 2:
            level.positions *= 1.2  # in place
            lifted["ids"] = level.ids.copy()

    refined = h.refine(op=lift)
    radius = np.linalg.norm(refined.positions, axis=1)
    moved = np.isin(refined.attributes["ids"], lifted["ids"])
    np.testing.assert_allclose(radius[moved], 1.2, rtol=1e-12)
    # Later levels insert on the moved surface (§4.5.1): every finer vertex followed it.
    assert (~moved).sum() > 0 and radius[~moved].min() > 1.1, radius[~moved].min()

    # Returning new positions is the same as moving them in place.
    again = h.refine(op=lambda level: level.positions * 1.2 if level.level == 2 else None)
    np.testing.assert_array_equal(again.positions, refined.positions)


def test_the_level_analysis_is_asperity_analyze_of_the_level(sphere):
    _, _, h = sphere
    got = {}

    def analyse(level):
        if level.level == 1:
            got["analysis"] = level.analysis()
            got["mesh"] = (level.positions.copy(), level.faces.copy())

    h.refine(op=analyse)
    direct = asperity.analyze(got["mesh"])
    assert set(got["analysis"]) == set(direct)
    for key, values in direct.items():
        np.testing.assert_array_equal(got["analysis"][key], values, err_msg=key)


def test_an_exception_in_the_operator_arrives_unchanged(sphere):
    _, _, h = sphere

    class Stop(Exception):
        pass

    raised = Stop("at level 1")

    def fail(level):
        if level.level == 1:
            raise raised

    with pytest.raises(Stop) as caught:
        h.refine(op=fail)
    assert caught.value is raised


def test_positions_an_operator_breaks_are_input_errors_naming_the_level(sphere):
    _, _, h = sphere
    with pytest.raises(asperity.InputError, match=r"level 0: positions has shape \(3, 3\)"):
        h.refine(op=lambda level: np.zeros((3, 3)))

    def poison(level):
        level.positions[5, 1] = np.nan

    with pytest.raises(asperity.InputError, match="level 0: position 5 is not finite"):
        h.refine(op=poison)
    with pytest.raises(asperity.InputError, match="op must be a function"):
        h.refine(op=3)


def test_an_operator_over_a_region_refines_the_region_and_what_it_needs(sphere):
    positions, _, h = sphere
    region = positions[:, 2] > 0.3
    visited = []
    refined = h.refine(region, op=lambda level: visited.append(len(level)))
    ids = refined.attributes["ids"]
    assert region[ids].sum() == region.sum()  # every region vertex is in
    assert len(ids) < len(positions) and (~region[ids]).sum() < (~region).sum()
    assert visited == sorted(visited) and len(visited) == h.levels
    report = h.refine_report
    assert report["region_vertices"] == region.sum() <= report["with_dependencies"], report
    coarse_rest = h.refine(region=region, base_level=h.levels // 2, op=lambda level: None)
    assert len(refined.positions) < len(coarse_rest.positions) < len(positions)


def test_the_build_report_is_simplify_json(meshes, cli, tmp_path):
    h = asperity.Hierarchy(asperity.read(meshes / "femur.off"), target_vertices=500, keep_features="none")
    report = h.report
    out = json.loads(
        run_cli(cli, "simplify", str(meshes / "femur.off"), "--target-vertices", "500", "--keep-features", "none",
                "--json", "-o", str(tmp_path / "base.ply"), cwd=tmp_path)
    )
    timed = {"seconds", "stage_seconds", "total_seconds"}
    assert set(out) - {"input", "output", "repair", "total_seconds"} == set(report)
    for key in set(report) - timed:
        assert report[key] == out[key], key
    assert report["target"]["reached"] and report["output_vertices"] == len(h.level(0)[0]) <= 500
    assert 0 < report["hausdorff"] < 0.05
    under = report["target"]["clusters_under_floor"]
    assert (f"{under} nearly free clusters" in report["gave_way"]) == (under > 0), report["gave_way"]


def test_options_are_typed_keywords(sphere):
    positions, triangles, _ = sphere
    with pytest.raises(TypeError, match="target_vertice"):
        asperity.Hierarchy(positions, triangles, target_vertice=10)
    with pytest.raises(asperity.InputError, match="keep_features=: unknown variant `corner`"):
        asperity.Hierarchy(positions, triangles, keep_features="corner")
    unguarded = asperity.Hierarchy(positions, triangles, target_vertices=100, intersection_guard=False)
    guarded = asperity.Hierarchy(positions, triangles, target_vertices=100)
    assert unguarded.report["output_vertices"] <= 100
    # Off, the guard's stage only collects nothing (microseconds); on, it tests every level
    # (milliseconds): three orders of magnitude apart, far beyond any machine's noise.
    assert unguarded.report["stage_seconds"]["guard"] * 20 < guarded.report["stage_seconds"]["guard"]


def test_results_come_back_as_trimesh_objects(sphere):
    trimesh = pytest.importorskip("trimesh", reason="trimesh did not install (optional: the interop helpers)")
    positions, triangles, h = sphere
    refined = h.refine().to_trimesh()
    assert isinstance(refined, trimesh.Trimesh) and len(refined.vertices) == len(positions)
    assert refined.is_watertight
    assert refined.area == pytest.approx(trimesh.Trimesh(positions, triangles, process=False).area, rel=1e-12)
    np.testing.assert_array_equal(refined.vertex_attributes["ids"], h.refined_ids)


def test_a_progress_function_watches_and_cancels_builds_and_refinements(sphere):
    positions, triangles, h = sphere
    reports = []
    built = asperity.Hierarchy(positions, triangles, target_vertices="5%",
                               progress=lambda stage, done, total: reports.append((stage, done, total)))
    assert len(reports) >= 3 and all(0 <= d <= t for _, d, t in reports), reports
    np.testing.assert_array_equal(built.level(0)[1], h.level(0)[1])  # watching changes nothing

    calls = []

    def stop_at_third(stage, done, total):
        calls.append(stage)
        return len(calls) < 3

    with pytest.raises(asperity.Cancelled, match="cancelled by the progress callback"):
        asperity.Hierarchy(positions, triangles, target_vertices="5%", progress=stop_at_third)
    assert len(calls) == 3

    class Stop(Exception):
        pass

    def raise_it(stage, done, total):
        raise Stop(stage)

    with pytest.raises(Stop):
        asperity.Hierarchy(positions, triangles, target_vertices="5%", progress=raise_it)

    levels = []
    h.refine(op=lambda level: None, progress=lambda stage, done, total: levels.append((stage, done, total)))
    assert levels == [("refine", k, h.levels - 1) for k in range(1, h.levels)]
    with pytest.raises(asperity.Cancelled):
        h.refine(op=lambda level: None, progress=lambda *report: False)
    seen = []
    h.refine(progress=lambda stage, done, total: seen.append(stage))
    assert "refine" in seen
    with pytest.raises(asperity.Cancelled):
        h.refine(progress=lambda *report: False)
    with pytest.raises(TypeError, match="progress must be"):
        asperity.Hierarchy(positions, triangles, progress="yes")
    # numpy's False stops too; None goes on.
    with pytest.raises(asperity.Cancelled):
        asperity.Hierarchy(positions, triangles, progress=lambda stage, done, total: np.int64(done) < 0)
    asperity.Hierarchy(positions, triangles, progress=lambda *report: None)


def test_asperity_called_from_a_progress_callback_is_refused_not_a_hang(sphere):
    positions, triangles, h = sphere
    nested = []

    def call_back_in(stage, done, total):
        nested.append(asperity.hausdorff((positions, triangles), (positions, triangles)))

    with pytest.raises(RuntimeError, match="cannot be called from a progress callback"):
        asperity.Hierarchy(positions, triangles, progress=call_back_in)
    assert nested == []
    # From an operator (between levels, on the calling thread) any call is fine.
    distances = []
    h.refine(op=lambda level: distances.append(asperity.hausdorff((level.positions, level.faces), (level.positions, level.faces))))
    assert len(distances) == h.levels and max(distances) < 1e-9


def test_threads_build_and_refine_side_by_side(sphere):
    """The documented thread-safety: calls from several threads are safe (each long call
    runs with the GIL released, one at a time), and one hierarchy serves concurrent
    refinements with results equal to one thread's."""
    import threading

    positions, triangles, h = sphere
    alone = h.refine(op=lambda level: level.positions.__imul__(1.01)).positions
    built, refined, failures = [], [], []

    def build():
        try:
            built.append(asperity.Hierarchy(positions, triangles, target_vertices="5%").level(0)[1])
        except Exception as e:  # noqa: BLE001 — reported below
            failures.append(e)

    def refine():
        try:
            refined.append(h.refine(op=lambda level: level.positions.__imul__(1.01)).positions)
        except Exception as e:  # noqa: BLE001
            failures.append(e)

    threads = [threading.Thread(target=f) for f in (build, refine, build, refine)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not failures, failures
    for b in built:
        np.testing.assert_array_equal(b, h.level(0)[1])
    for r in refined:
        np.testing.assert_array_equal(r, alone)


def test_a_numpy_operator_equals_the_same_cpp_operator_bit_for_bit():
    """The notebook-style target of #39: every level displaced along its normals by
    0.002 (level + 1) in numpy gives the C++ operator's result exactly
    (examples/cpp/integration.cpp writes its input and result; scripts/cpp-example.sh runs
    it, before these tests in make test)."""
    files = cpp_example_output("normal-displacement", ["input-positions.f64", "input-triangles.u32", "result-positions.f64"])
    positions, triangles = raw_rows(files["input-positions.f64"]), raw_rows(files["input-triangles.u32"])
    cpp = raw_rows(files["result-positions.f64"])
    h = asperity.Hierarchy(positions, triangles, target_vertices=len(positions) // 20, keep_features="none")

    def displace(level):
        level.positions += 0.002 * (level.level + 1) * level.normals

    result = h.refine(op=displace)
    ours = np.empty_like(result.positions)
    ours[result.attributes["ids"]] = result.positions
    assert np.abs(ours - positions).max() > 0.01  # the operator moved the surface
    np.testing.assert_array_equal(ours, cpp)


def test_progress_true_prints_the_refinement_and_false_prints_nothing(sphere, capfd):
    _, _, h = sphere
    h.refine(op=lambda level: None)
    h.refine()
    assert capfd.readouterr().err == ""
    h.refine(op=lambda level: None, progress=True)
    assert "refine: 100%" in capfd.readouterr().err
    h.refine(progress=True)
    assert "refine: 100%" in capfd.readouterr().err
