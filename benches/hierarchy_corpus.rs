//! #34's corpus benchmark: ours and meshoptimizer at 1 %, 5 %, 10 % and 25 % of every mesh
//! of `benches/corpus/manifest.tsv` (fetched by `scripts/fetch-corpus.sh` into
//! `target/corpus/`), side by side in one run. Per mesh and ratio one line; per class the
//! median and worst ratio of Hausdorff at the requested target (and at the smallest count
//! both reached, where meshoptimizer stops short), how many reached their target (within
//! 1 % or the topology's floor), and the smallest angle and sliver share against the
//! input's. `cuts in/o/m` counts the face pairs that intersect in the input, ours and
//! meshoptimizer's result: where meshoptimizer reaches a count ours stops short of, it
//! shows whether it got there by cutting the surface.
//!
//! `ASPERITY_CORPUS_CLASS=cad-sharp` runs one class, `ASPERITY_CORPUS_RATIOS=10` chosen
//! ratios (percent, comma-separated), `ASPERITY_CORPUS_HELD_OUT=yes|no` one half.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use asperity::hierarchy::compare::{CompareRow, ShapeReport, compare_report, same_count};
use asperity::hierarchy::{SimplifyOptions, topological_floor};
use asperity::mesh::{Mesh, ValidationReport, repair};

/// One manifest row.
struct Entry {
    name: String,
    class: String,
    file: PathBuf,
    held_out: bool,
}

/// One mesh at one ratio.
struct Outcome {
    class: String,
    /// Hausdorff ours / meshoptimizer's at the requested target.
    at_target: f64,
    /// The same at the smallest count both reached (= `at_target` when both reached it).
    at_common: f64,
    reached: bool,
    min_angle_ok: bool,
    slivers_ok: bool,
}

fn manifest(root: &Path) -> Vec<Entry> {
    let path = root.join("benches/corpus/manifest.tsv");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("a header line").split('\t').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no column {name}"));
    let (name, class, file, held) = (column("name"), column("class"), column("file"), column("held_out"));
    lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let cells: Vec<&str> = l.split('\t').collect();
            Entry {
                name: cells[name].to_string(),
                class: cells[class].to_string(),
                file: root.join("target/corpus").join(cells[file]),
                held_out: cells[held] == "yes",
            }
        })
        .collect()
}

fn ratios() -> Vec<f64> {
    std::env::var("ASPERITY_CORPUS_RATIOS")
        .ok()
        .map(|s| s.split(',').map(|r| r.trim().parse().expect("a ratio in percent")).collect())
        .unwrap_or_else(|| vec![1.0, 5.0, 10.0, 25.0])
}

/// The mesh as the build takes it: read, and repaired when it is not an oriented manifold
/// without degenerate faces (as `--repair` does). Texture coordinates and materials are
/// left out: meshoptimizer is run on positions alone, and ours keeps seams as lines that
/// never give way, so with them the two would not compare like with like.
fn prepared(entry: &Entry) -> Option<Mesh> {
    let mesh = match asperity::io::read(&entry.file) {
        Ok(read) => Mesh { uvs: None, materials: None, ..read.mesh },
        Err(e) => {
            println!("{:<24} unreadable: {e}", entry.name);
            return None;
        }
    };
    let report = ValidationReport::of(&mesh);
    let clean = report.is_manifold()
        && report.inconsistently_oriented_edges == 0
        && report.degenerate_faces == 0
        && report.unreferenced_vertices == 0;
    if clean {
        return Some(mesh);
    }
    match repair(&mesh) {
        Ok((mesh, _)) => Some(mesh),
        Err(e) => {
            println!("{:<24} not repairable: {e}", entry.name);
            None
        }
    }
}

fn row<'a>(rows: &'a [CompareRow], method: &str) -> &'a CompareRow {
    rows.iter().find(|r| r.method == method).expect("a row per method")
}

fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    values.get(values.len() / 2).copied().unwrap_or(f64::NAN)
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let entries = manifest(root);
    let missing: Vec<&Entry> = entries.iter().filter(|e| !e.file.is_file()).collect();
    assert!(
        missing.is_empty(),
        "{} corpus meshes are missing, first {}: run scripts/fetch-corpus.sh (it fetches them into target/corpus/)",
        missing.len(),
        missing.first().map_or(String::new(), |e| e.file.display().to_string())
    );
    let class_filter = std::env::var("ASPERITY_CORPUS_CLASS").ok();
    let held_filter = std::env::var("ASPERITY_CORPUS_HELD_OUT").ok().map(|h| h == "yes");
    let ratios = ratios();
    let mut outcomes: Vec<Outcome> = Vec::new();
    println!(
        "{:<24} {:>5} {:>7} {:>7} {:>7} {:>8} {:>8} {:>6} {:>7} {:>7} {:>7} {:>11}  gave way",
        "mesh",
        "ratio",
        "target",
        "ours",
        "mo",
        "ours H%",
        "mo H%",
        "ratio",
        "common",
        "minang",
        "slivers",
        "cuts in/o/m"
    );
    for entry in &entries {
        if class_filter.as_ref().is_some_and(|c| *c != entry.class) || held_filter.is_some_and(|h| h != entry.held_out)
        {
            continue;
        }
        let Some(mesh) = prepared(entry) else { continue };
        let input_shape = ShapeReport::of(&mesh);
        let floor = topological_floor(mesh.vertex_count(), &mesh.triangles);
        for &ratio in &ratios {
            let target = ((mesh.vertex_count() as f64 * ratio / 100.0).round() as usize).max(4);
            let options = SimplifyOptions::default();
            let report = match compare_report(&mesh, target, &["asperity", "meshoptimizer"], &options) {
                Ok(report) => report,
                Err(e) => {
                    println!("{:<24} {ratio:>4}% failed: {e}", entry.name);
                    continue;
                }
            };
            let (ours, mo) = (row(&report.at_target, "asperity"), row(&report.at_target, "meshoptimizer"));
            let common = report
                .at_common_count
                .as_ref()
                .map_or((ours, mo), |c| (row(&c.rows, "asperity"), row(&c.rows, "meshoptimizer")));
            let ratio_of = |a: &CompareRow, b: &CompareRow| {
                if b.hausdorff > 0.0 {
                    a.hausdorff / b.hausdorff
                } else if a.hausdorff > 0.0 {
                    f64::INFINITY
                } else {
                    1.0
                }
            };
            let reached = ours.vertices <= target.max(floor) || same_count(ours.vertices, target.max(floor));
            let reached = reached || ours.vertices as f64 <= 1.01 * target as f64;
            let outcome = Outcome {
                class: entry.class.clone(),
                at_target: ratio_of(ours, mo),
                at_common: ratio_of(common.0, common.1),
                reached,
                min_angle_ok: input_shape.min_angle_deg < 0.5 || ours.min_angle_deg >= 0.5,
                slivers_ok: input_shape.min_angle_deg < 0.5 || ours.sliver_share <= input_shape.sliver_share + 1e-12,
            };
            println!(
                "{:<24} {:>4}% {:>7} {:>7} {:>7} {:>8.3} {:>8.3} {:>6.2} {:>7.2} {:>7.2} {:>6.1}% {:>11}  {}{}",
                entry.name,
                ratio,
                target,
                ours.vertices,
                mo.vertices,
                ours.hausdorff * 100.0,
                mo.hausdorff * 100.0,
                outcome.at_target,
                outcome.at_common,
                ours.min_angle_deg,
                ours.sliver_share * 100.0,
                format!("{}/{}/{}", report.input_self_intersections, ours.self_intersections, mo.self_intersections),
                ours.gave_way.as_deref().unwrap_or(""),
                if outcome.reached { "" } else { " — TARGET NOT REACHED" }
            );
            if let Some(why) = &ours.stopped_by {
                println!("{:<24} stopped by {why}", "");
            }
            outcomes.push(outcome);
        }
    }
    let mut classes: BTreeMap<&str, Vec<&Outcome>> = BTreeMap::new();
    for o in &outcomes {
        classes.entry(o.class.as_str()).or_default().push(o);
    }
    println!();
    println!(
        "{:<14} {:>5} {:>9} {:>9} {:>9} {:>9} {:>8} {:>9} {:>9}",
        "class", "runs", "median", "worst", "med.comm", "worst.c", "reached", "angle ok", "slivers"
    );
    for (class, list) in &classes {
        let mut at: Vec<f64> = list.iter().map(|o| o.at_target).collect();
        let mut common: Vec<f64> = list.iter().map(|o| o.at_common).collect();
        let worst = at.iter().copied().fold(0.0, f64::max);
        let worst_common = common.iter().copied().fold(0.0, f64::max);
        let count = |f: &dyn Fn(&Outcome) -> bool| list.iter().filter(|o| f(o)).count();
        println!(
            "{:<14} {:>5} {:>9.3} {:>9.3} {:>9.3} {:>9.3} {:>4}/{:<3} {:>5}/{:<3} {:>5}/{:<3}",
            class,
            list.len(),
            median(&mut at),
            worst,
            median(&mut common),
            worst_common,
            count(&|o| o.reached),
            list.len(),
            count(&|o| o.min_angle_ok),
            list.len(),
            count(&|o| o.slivers_ok),
            list.len()
        );
    }
}
