//! The C++ package's option structs and Python's typed keywords name the library requests'
//! fields (#38): a field added to a request and not to its C++ struct or Python signature,
//! or a member the request does not know, fails here instead of drifting (Python's
//! `**options` keywords are the request's fields themselves, read by `request::from_fields`,
//! so they cannot drift).

use std::collections::BTreeSet;
use std::path::Path;

use asperity::analysis::AnalysisRequest;
use asperity::hierarchy::HierarchyRequest;
use asperity::noise::NoiseRequest;
use asperity::terrain::{TerrainRequest, TerrainTile};

/// The data members of `struct NAME { … };` in a header of the C++ package: lines of the
/// form `  TYPE name;` or `  TYPE name = …;` at the struct's first indentation.
fn members(header: &str, name: &str) -> BTreeSet<String> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cpp/package").join(header);
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: the C++ package's header should be here ({e})", path.display()));
    let start = text.find(&format!("struct {name} {{")).unwrap_or_else(|| panic!("no struct {name} in {header}"));
    let body = &text[start..];
    let body = &body[..body.find("\n};").unwrap_or_else(|| panic!("struct {name} does not end in {header}"))];
    body.lines()
        .filter(|line| line.starts_with("  ") && !line.starts_with("   ") && !line.trim_start().starts_with("//"))
        .filter_map(|line| {
            let declaration = line.trim().strip_suffix(';')?;
            let declaration = declaration.split(" = ").next()?;
            if declaration.contains('(') {
                return None; // a constructor or a method
            }
            declaration.rsplit(' ').next().map(str::to_string)
        })
        .collect()
}

/// The keyword-only parameters of `def NAME(` inside `class CLASS` of the Python package.
fn keywords(class: &str, name: &str) -> BTreeSet<String> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("python/asperity/__init__.py");
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: the Python package should be here ({e})", path.display()));
    let class_at = text.find(&format!("class {class}")).unwrap_or_else(|| panic!("no class {class}"));
    let def_at = class_at + text[class_at..].find(&format!("def {name}(")).unwrap_or_else(|| panic!("no {name}"));
    let signature = &text[def_at..def_at + text[def_at..].find(") -> ").expect("a signature's end")];
    let after_star = signature.split_once("*,").map_or("", |(_, rest)| rest);
    after_star
        .lines()
        .filter_map(|line| line.trim().split_once(':').map(|(name, _)| name.trim().to_string()))
        .filter(|name| !name.is_empty())
        .collect()
}

/// The fields a request reads, as its JSON form names them.
fn fields<R: serde::Serialize + Default>() -> BTreeSet<String> {
    match serde_json::to_value(R::default()).expect("a request serialises") {
        serde_json::Value::Object(map) => map.keys().cloned().collect(),
        other => panic!("a request serialises to an object, not {other}"),
    }
}

fn set(names: &[&str]) -> BTreeSet<String> {
    names.iter().map(|n| n.to_string()).collect()
}

/// The names a front end declares (`declared`) against its request's fields: the ones it
/// may have beyond the request (`front_end_only`) and the fields it may lack
/// (`request_only`), each with its reason at the call.
fn assert_mirrors(
    front_end: &str,
    declared: BTreeSet<String>,
    request: BTreeSet<String>,
    front_end_only: &[&str],
    request_only: &[&str],
) {
    let extra: BTreeSet<String> = declared.difference(&request).cloned().collect();
    let missing: BTreeSet<String> = request.difference(&declared).cloned().collect();
    assert_eq!(extra, set(front_end_only), "{front_end} has names its request does not read");
    assert_eq!(missing, set(request_only), "{front_end} lacks fields of its request");
}

#[test]
fn the_cpp_option_structs_and_python_keywords_name_their_requests_fields() {
    let mut terrain = fields::<TerrainRequest>();
    terrain.extend(fields::<TerrainTile>());
    terrain.insert("layers".into()); // left out of the JSON form while empty
    assert_mirrors(
        "C++ TerrainOptions",
        members("terrain.hpp", "TerrainOptions"),
        terrain,
        &[],
        // iterations/roughness: other spellings of size/hurst; steps: a folder the command
        // line writes; preset, range, layers: file outputs and the layers' own call, which
        // the C++ package does not have.
        &["iterations", "layers", "preset", "range", "roughness", "steps"],
    );
    assert_mirrors("C++ NoiseOptions", members("noise.hpp", "NoiseOptions"), fields::<NoiseRequest>(), &[], &[]);
    assert_mirrors(
        "C++ AnalysisOptions",
        members("analysis.hpp", "AnalysisOptions"),
        fields::<AnalysisRequest>(),
        &[],
        &[],
    );
    assert_mirrors(
        "C++ HierarchyOptions",
        members("hierarchy.hpp", "HierarchyOptions"),
        fields::<HierarchyRequest>(),
        // keep_vertices (input ids never removed), Algorithm 3's threshold and the progress
        // callback are the build's settings beyond a recipe's table.
        &["fix_threshold_degrees", "keep_vertices", "progress"],
        &[],
    );
    assert_mirrors(
        "Python Hierarchy(...)",
        keywords("Hierarchy", "__init__"),
        fields::<HierarchyRequest>(),
        // Input repair and the progress callback are the call's, not the build's settings.
        &["progress", "repair"],
        &[],
    );
    assert_mirrors(
        "C++ HierarchySettings",
        members("pipeline.hpp", "HierarchySettings"),
        fields::<HierarchyRequest>(),
        &[],
        &[],
    );
}
