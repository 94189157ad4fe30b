//! The terrain request (#38): read strictly from fields as Python and C++ send them, its
//! text and list forms alike, the written form plans are fingerprinted from unchanged, and
//! its heights and meshes equal what `asperity terrain` writes.

use std::process::Command;

use asperity::request::Spelling;
use asperity::terrain::{ErosionLayer, ErosionModel, TerrainMethod, TerrainRequest, TerrainTile};

fn read(json: &str) -> asperity::Result<(TerrainRequest, TerrainTile)> {
    TerrainRequest::from_fields(json, Spelling::Keyword)
}

fn message(json: &str) -> String {
    read(json).expect_err(json).to_string()
}

#[test]
fn fields_are_read_strictly_and_named_as_the_front_end_spells_them() {
    let unknown = message(r#"{"size": 33, "bogus": 1}"#);
    assert!(unknown.contains("bogus= is not an option here"), "{unknown}");
    // Fields taken apart by the reader are listed among the options too.
    for listed in ["layers=", "tile=", "tile_size=", "erode_iterations="] {
        assert!(unknown.contains(listed), "{listed} missing from: {unknown}");
    }
    // A field refused here (dual's steps folder, a file the command line writes) is not
    // offered as an option.
    assert!(!unknown.contains("steps="), "{unknown}");
    let typed = message(r#"{"size": "large"}"#);
    assert!(typed.contains(": size=: invalid type"), "{typed}");
    let file = message(r#"{"preview": "x.png"}"#);
    assert!(file.contains("preview= applies to the command line's asperity terrain"), "{file}");
    let twice = message(r#"{"iterations": 5, "size": 33}"#);
    assert_eq!(twice, "invalid input: iterations= and size= set the same thing: give one");
    let member = TerrainRequest::from_fields(r#"{"max_height": 2, "sigma": 3}"#, Spelling::Member).unwrap_err();
    assert!(member.to_string().contains("option .max_height and option .sigma"), "{member}");
    let tile = message(r#"{"tile": [1, 2, 3], "tile_size": 17}"#);
    assert!(tile.contains(": tile=: "), "{tile}");
    let (request, tile) = read(r#"{"size": 65, "tile": [1, 0], "tile_size": 33, "seed": null}"#).unwrap();
    assert_eq!((request.size, request.seed), (Some(65), 0));
    assert_eq!((tile.tile, tile.tile_size), (Some((1, 0)), Some(33)));
}

#[test]
fn lists_and_colours_read_alike_as_text_and_as_lists() {
    let text = read(r#"{"erode": "thermal,hydraulic", "layers": "flow, water"}"#).unwrap().0;
    let lists = read(r#"{"erode": ["thermal", "hydraulic"], "layers": ["flow", "water"]}"#).unwrap().0;
    assert_eq!(text, lists);
    assert_eq!(text.erode, [ErosionModel::Thermal, ErosionModel::Hydraulic]);
    assert_eq!(text.layers, [ErosionLayer::Flow, ErosionLayer::Water]);
    let one = read(r#"{"erode": "hydraulic"}"#).unwrap().0;
    assert_eq!(one.erode, [ErosionModel::Hydraulic]);
    let wrong = message(r#"{"erode": "thermal,wind"}"#);
    assert!(wrong.contains(": erode=: unknown variant `wind`"), "{wrong}");
    let ramp = "1,2,3;4,5,6;7,8,9;10,11,12;13,14,15";
    let from_text = read(&format!(r#"{{"colors": "{ramp}"}}"#)).unwrap().0;
    let from_list = read(r#"{"colors": [[1,2,3],[4,5,6],[7,8,9],[10,11,12],[13,14,15]]}"#).unwrap().0;
    assert_eq!(from_text, from_list);
    assert_eq!(from_text.colors.unwrap().peak, [13, 14, 15]);
    assert!(message(r#"{"colors": [[1,2,3]]}"#).contains(": colors=: "));
    let channel = message(r#"{"colors": "1,2,3;4,5,6;7,8,9;10,11,12;13,14,256"}"#);
    assert!(channel.contains("colors=: `256` is not a value from 0 to 255"), "{channel}");
    let listed = message(r#"{"colors": [[1,2,3],[4,5,6],[7,8,9],[10,11,12],[13,14,256]]}"#);
    assert!(listed.contains("colors=: ") && listed.contains("256"), "{listed}");
    // Python's `stream=False` leaves the file field out, as None does.
    assert!(read(r#"{"size": 17, "stream": false, "sidecar": null}"#).is_ok());
}

/// Plans are fingerprinted from the request as it is written: its form is part of every
/// planned tile's sidecar, and a change would make complete tiles look stale.
#[test]
fn the_written_form_plans_are_fingerprinted_from_is_unchanged() {
    let written = serde_json::to_string(&TerrainRequest::default()).unwrap();
    assert_eq!(
        written,
        concat!(
            r#"{"method":"classic","size":null,"iterations":null,"hurst":null,"roughness":null,"sigma":1.0,"#,
            r#""x":null,"y":null,"levels":null,"deterministic":false,"cross_product":false,"#,
            r#""no_mean_correction":false,"steps":null,"seed":0,"distribution":null,"mean":null,"variance":null,"#,
            r#""corners":null,"applet":false,"width":null,"depth":null,"max_height":null,"sea_level":null,"#,
            r#""colors":null,"peak_height":null,"grid":null,"range":null,"erode":[],"erode_iterations":null,"#,
            r#""talus":null,"rain":null,"evaporation":null,"capacity":null,"dissolving":null,"deposition":null,"#,
            r#""time_step":null,"preset":null}"#
        )
    );
    // A plan written before hydraulic erosion stored one model, or null.
    let old: TerrainRequest = serde_json::from_str(r#"{"method": "smooth", "erode": "thermal"}"#).unwrap();
    assert_eq!((old.method, old.erode.as_slice()), (TerrainMethod::Smooth, &[ErosionModel::Thermal][..]));
    let none: TerrainRequest = serde_json::from_str(r#"{"erode": null}"#).unwrap();
    assert!(none.erode.is_empty());
}

#[test]
fn parameters_of_another_mode_are_refused_naming_it() {
    let dual = read(r#"{"method": "dual", "size": 33}"#).unwrap().0;
    let refused = dual.mesh(TerrainTile::default(), Spelling::Keyword).unwrap_err().to_string();
    assert!(refused.contains("size= applies only to method=classic and smooth: with method=dual"), "{refused}");
    let heights = read(r#"{"method": "dual"}"#).unwrap().0;
    let surface = heights.heights(TerrainTile::default(), Spelling::Keyword).unwrap_err().to_string();
    assert!(surface.contains("method=dual makes a 3D surface"), "{surface}");
    let range = read(r#"{"size": 17, "range": [-1, 1]}"#).unwrap().0;
    let range = range.heights(TerrainTile::default(), Spelling::Keyword).unwrap_err().to_string();
    assert!(range.contains("range= applies only to 16-bit outputs"), "{range}");
    let (request, tile) = read(r#"{"size": 17, "tile": [0, 0]}"#).unwrap();
    let alone = request.heights(tile, Spelling::Keyword).unwrap_err().to_string();
    assert!(alone.contains("tile= needs tile_size="), "{alone}");
    let layers = read(r#"{"size": 17, "erode": "hydraulic", "layers": "flow"}"#).unwrap().0;
    assert!(layers.mesh(TerrainTile::default(), Spelling::Keyword).is_err());
    assert!(layers.heights(TerrainTile::default(), Spelling::Keyword).is_err());
    assert_eq!(layers.heights_and_layers(TerrainTile::default(), Spelling::Keyword).unwrap().1.len(), 1);
}

/// The library's heights and mesh are what the command writes for the same parameters.
#[test]
fn heights_and_meshes_equal_what_the_command_writes() {
    let dir = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_asperity")).args(args).current_dir(dir.path()).output().unwrap();
        assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    };
    let flags = ["--size", "65", "--seed", "4", "--erode", "thermal", "--erode-iterations", "3", "--tile", "1,0"];
    run(&[&["terrain"][..], &flags, &["--tile-size", "33", "-o", "t.f32"]].concat());
    let fields =
        r#"{"size": 65, "seed": 4, "erode": "thermal", "erode_iterations": 3, "tile": [1, 0], "tile_size": 33}"#;
    let (request, tile) = read(fields).unwrap();
    let heights = request.heights(tile, Spelling::Keyword).unwrap();
    let written: Vec<u8> = std::fs::read(dir.path().join("t.f32")).unwrap();
    let made: Vec<u8> = heights.heights.iter().flat_map(|&h| (h as f32).to_le_bytes()).collect();
    assert_eq!(made, written);
    run(&[
        "terrain",
        "--method",
        "dual",
        "--levels",
        "4",
        "--seed",
        "2",
        "--colors",
        "0,0,0;9,9,9;50,50,50;90,90,90;255,0,0",
        "-o",
        "d.ply",
    ]);
    let dual = read(r#"{"method": "dual", "levels": 4, "seed": 2, "colors": "0,0,0;9,9,9;50,50,50;90,90,90;255,0,0"}"#)
        .unwrap()
        .0;
    let mesh = dual.mesh(TerrainTile::default(), Spelling::Keyword).unwrap();
    let file = asperity::io::read(&dir.path().join("d.ply")).unwrap();
    assert_eq!(mesh.triangles, file.mesh.triangles);
    assert_eq!(mesh.colors, file.mesh.colors);
    assert_eq!(mesh.positions, file.mesh.positions);
}

/// A plan written by the previous layout (a79daa0's `asperity terrain plan --size 129
/// --tile-size 65 --erode thermal,hydraulic --erode-iterations 2 --layers water,flow
/// --sea-level 0.1 --seed 9 --hurst 0.6 --range -2,3`): its parameters read back and
/// are written the same, and the plan made from them has the same fingerprint, so its
/// complete tiles stay complete.
#[test]
fn a_plan_of_the_previous_layout_keeps_its_fingerprint() {
    use asperity::terrain::plan::Plan;
    use asperity::terrain::{TerrainOutput, TerrainTarget};
    let written = concat!(
        r#"{"method":"classic","size":129,"iterations":null,"hurst":0.6,"roughness":null,"sigma":1.0,"x":null,"#,
        r#""y":null,"levels":null,"deterministic":false,"cross_product":false,"no_mean_correction":false,"#,
        r#""steps":null,"seed":9,"distribution":null,"mean":null,"variance":null,"corners":null,"applet":false,"#,
        r#""width":null,"depth":null,"max_height":null,"sea_level":0.1,"colors":null,"peak_height":null,"#,
        r#""grid":null,"range":[-2.0,3.0],"erode":["thermal","hydraulic"],"erode_iterations":2,"talus":null,"#,
        r#""rain":null,"evaporation":null,"capacity":null,"dissolving":null,"deposition":null,"time_step":null,"#,
        r#""layers":["water","flow"],"preset":null}"#
    );
    let request: TerrainRequest = serde_json::from_str(written).unwrap();
    assert_eq!(serde_json::to_string(&request).unwrap(), written);
    let target = TerrainTarget {
        output: TerrainOutput::Heightmap16,
        tile: Some((0, 0)),
        tile_size: Some(65),
        sidecar: true,
        ..TerrainTarget::default()
    };
    let setup = request.layout(&target, Spelling::Flag).unwrap().ready(&target, Spelling::Flag).unwrap();
    let plan = Plan::new(&request, &setup, 65, "png", std::path::Path::new("p")).unwrap();
    assert_eq!(plan.fingerprint, "86fcefbb21a7bf60");
}
