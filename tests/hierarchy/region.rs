//! Region refinement (#26 C11, thesis §4.6): a region at the input's resolution, the rest at
//! a coarser level — a conforming manifold of the input's genus with every region vertex,
//! no self-intersection, and Algorithms 2 and 3 exercised where the recorded faces are
//! gone; the `refine` command reports what each rule placed.

use std::process::Command;

use asperity::detail::{Selection, input_selection};
use asperity::hierarchy::region::refine_region;
use asperity::hierarchy::{Hierarchy, LevelReport, SimplifyOptions, build};
use asperity::mesh::{Mesh, primitives};

use crate::common::{shared_meshes, temp_dir};

fn region(text: &str) -> Selection {
    toml::from_str(text).unwrap()
}

/// Refines `mesh` in `selection` from `base_level` and checks the result; returns what
/// each rule placed, summed over levels.
fn region_refines(name: &str, hierarchy: &Hierarchy, mesh: &Mesh, selection: &str, base_level: usize) -> LevelReport {
    let inside = input_selection(mesh, &region(selection), 0).unwrap();
    let wanted = inside.iter().filter(|&&i| i).count();
    assert!(wanted > 0 && wanted < mesh.vertex_count(), "{name}: the region is part of the mesh ({wanted})");
    let refined = refine_region(hierarchy, base_level, &|v| inside[v as usize]).unwrap();
    let out = &refined.mesh.mesh;
    let report = out.validate();
    let input = mesh.validate();
    assert!(report.is_manifold() && report.inconsistently_oriented_edges == 0, "{name}: {report:?}");
    assert_eq!(report.genus, input.genus, "{name}: genus kept");
    assert_eq!(report.boundary_loops, input.boundary_loops, "{name}: boundaries kept");
    assert!(refined.missing.is_empty(), "{name}: region vertices missing: {:?}", refined.missing);
    for (v, _) in inside.iter().enumerate().filter(|(_, i)| **i) {
        assert!(refined.mesh.ids.binary_search(&(v as u32)).is_ok(), "{name}: region vertex {v} absent");
    }
    assert!(out.vertex_count() < mesh.vertex_count(), "{name}: the rest stays coarser");
    assert_eq!(asperity::ffi::self_intersections(out).unwrap().len(), 0, "{name}: self-intersections");
    assert_eq!(refined.self_intersections, 0);
    // Every vertex sits at its input position (nothing was deformed).
    for (i, &id) in refined.mesh.ids.iter().enumerate() {
        assert_eq!(out.positions[i], mesh.positions[id as usize], "{name}: vertex {id} moved");
    }
    refined.totals()
}

/// [`region_refines`] for each of `cases` (region, base level) over one hierarchy of `mesh`,
/// each checked; over all of them, Algorithm 2's search and Algorithm 3's widest-angle
/// flips must both have run (which removals find their recorded face gone depends on the
/// hierarchy, so no single region is certain to meet both).
fn assert_region_refines(name: &str, mesh: &Mesh, cases: &[(&str, usize)]) {
    let hierarchy = build(mesh, &SimplifyOptions::default()).unwrap();
    let (mut relocated, mut widest_flips) = (0, 0);
    for &(selection, base_level) in cases {
        let totals = region_refines(name, &hierarchy, mesh, selection, base_level);
        relocated += totals.relocated;
        widest_flips += totals.widest_flips;
    }
    assert!(relocated > 0, "{name}: Algorithm 2's search never ran over {cases:?}");
    assert!(widest_flips > 0, "{name}: Algorithm 3's widest-angle flips never ran over {cases:?}");
}

#[test]
fn a_torus_region_is_refined_to_full_resolution_and_the_rest_stays_coarse() {
    let torus = primitives::torus(1.0, 0.35, 96, 48);
    assert_region_refines("torus", &torus, &[("sphere = { center = [0.9, 0.5, 0.5], radius = 0.15 }", 0)]);
}

#[test]
fn a_fandisk_region_is_refined_over_a_coarser_level() {
    let fandisk = asperity::io::read(&shared_meshes().join("fandisk.off")).unwrap().mesh;
    // Regions across the fan's ridge and its creases, over coarser and finer levels.
    let ridge = "sphere = { center = [0.3, 0.6, 0.8], radius = 0.25 }";
    let top = "sphere = { center = [0.5, 0.5, 1.0], radius = 0.3 }";
    assert_region_refines("fandisk", &fandisk, &[(ridge, 3), (ridge, 6), (top, 3), (top, 6)]);
}

#[test]
fn refine_reports_each_rule_and_refuses_bad_regions() {
    let tmp = temp_dir();
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_asperity")).args(args).current_dir(tmp.path()).output().unwrap()
    };
    let out = run(&[
        "refine",
        "builtin:torus",
        "--region",
        "sphere = { center = [0.9, 0.5, 0.5], radius = 0.15 }",
        "-o",
        "r.ply",
        "--json",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for key in ["replayed", "searched", "widened", "flips", "widest_flips"] {
        assert!(report[key].is_u64(), "{key} in {report}");
    }
    assert_eq!(report["genus"], 1);
    assert_eq!(report["self_intersections"], 0);
    assert!(report["searched"].as_u64().unwrap() > 0);
    let mesh = asperity::io::read(&tmp.path().join("r.ply")).unwrap().mesh;
    assert_eq!(mesh.vertex_count() as u64, report["output_vertices"].as_u64().unwrap());
    for (args, says) in [
        (vec!["refine", "builtin:torus", "--region", "ball = { r = 1 }", "-o", "x.ply"], "--region"),
        (
            vec![
                "refine",
                "builtin:torus",
                "--region",
                "box = { min = [0,0,0], max = [1,1,1] }",
                "--base-level",
                "999",
                "-o",
                "x.ply",
            ],
            "base level 999",
        ),
    ] {
        let out = run(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains(says), "{stderr}");
        assert!(!tmp.path().join("x.ply").exists());
    }
}
