//! Pictures (#8): the rasteriser frames, lights, colours and hides what it should, the same
//! at any thread count; the hillshade faces the north-west sun; the CLI renders every shared
//! mesh and writes terrain previews.

use asperity::Mesh;
use asperity::mesh::primitives::{icosphere, torus};
use asperity::render::hillshade::{Relief, hillshade};
use asperity::render::{ColorSource, Mode, Picture, RenderOptions, UpAxis, render};
use glam::DVec3;

use crate::common::{shared_mesh_files, temp_dir};

fn small(mode: Mode) -> RenderOptions {
    RenderOptions { width: 160, height: 120, mode, ..RenderOptions::default() }
}

fn is_background(p: [u8; 4]) -> bool {
    p == [255, 255, 255, 255]
}

/// Columns and rows that hold anything but the background.
fn extent(picture: &Picture) -> (usize, usize) {
    let inked = |x: usize, y: usize| !is_background(picture.pixel(x, y));
    let cols = (0..picture.width).filter(|&x| (0..picture.height).any(|y| inked(x, y))).count();
    let rows = (0..picture.height).filter(|&y| (0..picture.width).any(|x| inked(x, y))).count();
    (cols, rows)
}

#[test]
fn a_sphere_fills_the_frame_and_is_lit_from_the_upper_left() {
    let picture = render(&icosphere(1.0, 4), &small(Mode::Faces)).unwrap();
    let (cols, rows) = extent(&picture);
    // The camera is fitted: the sphere spans ~92 % of the tighter side (the height).
    assert!((105..=115).contains(&rows), "{rows} rows of 120");
    assert!(cols < 125, "a sphere is round: {cols} columns");
    assert!(is_background(picture.pixel(0, 0)) && is_background(picture.pixel(159, 119)));
    let brightness = |x: usize, y: usize| picture.pixel(x, y)[..3].iter().map(|&c| c as u32).sum::<u32>();
    // Key light from the upper left: that side is brighter than the lower right.
    assert!(brightness(62, 35) > brightness(98, 85) + 60, "{} vs {}", brightness(62, 35), brightness(98, 85));
}

#[test]
fn both_sides_of_a_sheet_are_lit_alike() {
    let sheet = Mesh::new(
        vec![
            DVec3::new(-1.0, 0.0, -1.0),
            DVec3::new(1.0, 0.0, -1.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(-1.0, 0.0, 1.0),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    );
    let centre = |yaw: f64| {
        let options = RenderOptions { yaw_deg: yaw, pitch_deg: 0.0, ..small(Mode::Faces) };
        render(&sheet, &options).unwrap().pixel(80, 60)
    };
    let (front, back) = (centre(0.0), centre(180.0));
    assert!(!is_background(front) && !is_background(back));
    for k in 0..3 {
        assert!((front[k] as i32 - back[k] as i32).abs() <= 12, "front {front:?} back {back:?}");
    }
    assert!(front[0] > 120, "lit, not black: {front:?}");
}

#[test]
fn pictures_are_identical_at_one_and_two_threads() {
    let mesh = torus(1.0, 0.35, 64, 32);
    for mode in [Mode::Faces, Mode::Wireframe, Mode::Points] {
        let options = RenderOptions { colors: ColorSource::Height, edges: mode == Mode::Faces, ..small(mode) };
        let at = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| render(&mesh, &options).unwrap())
        };
        assert_eq!(at(1), at(2), "{mode:?}");
    }
}

#[test]
fn transparent_backgrounds_carry_coverage_in_alpha() {
    let options = RenderOptions { background: None, ..small(Mode::Faces) };
    let picture = render(&icosphere(1.0, 3), &options).unwrap();
    assert_eq!(picture.pixel(0, 0)[3], 0);
    assert_eq!(picture.pixel(80, 60)[3], 255);
    let partial = (0..160).flat_map(|x| (0..120).map(move |y| (x, y))).filter(|&(x, y)| {
        let a = picture.pixel(x, y)[3];
        a > 0 && a < 255
    });
    assert!(partial.count() > 20, "anti-aliased silhouette");
}

#[test]
fn height_colours_run_from_purple_at_the_bottom_to_yellow_at_the_top() {
    let options = RenderOptions { colors: ColorSource::Height, pitch_deg: 0.0, up: UpAxis::Z, ..small(Mode::Faces) };
    let picture = render(&icosphere(1.0, 4), &options).unwrap();
    let (top, bottom) = (picture.pixel(80, 12), picture.pixel(80, 108));
    assert!(top[0] > top[2] && top[1] > top[2], "yellowish top {top:?}");
    assert!(bottom[2] > bottom[1], "purple-blue bottom {bottom:?}");
}

#[test]
fn the_wireframe_hides_the_back_edges() {
    // Seen head-on, a sphere's wireframe is as dense near its rim as its front: with hidden
    // lines removed the far hemisphere's edges do not double the ink.
    let mesh = icosphere(1.0, 3);
    let ink = |picture: &Picture| (0..160 * 120).filter(|&i| !is_background(picture.pixel(i % 160, i / 160))).count();
    let hidden = ink(&render(&mesh, &small(Mode::Wireframe)).unwrap());
    let mut all = mesh.clone();
    all.triangles.clear();
    let points = ink(&render(&all, &small(Mode::Points)).unwrap());
    assert!(hidden > 2000, "{hidden} inked pixels");
    let shaded = render(&mesh, &small(Mode::Faces)).unwrap();
    assert!(hidden < ink(&shaded), "lines leave gaps between them");
    // Points without faces are all drawn, front and back.
    let front_only = ink(&render(&mesh, &small(Mode::Points)).unwrap());
    assert!(front_only < points, "hidden points removed: {front_only} < {points}");
}

#[test]
fn bad_requests_are_typed_errors() {
    let mesh = icosphere(1.0, 1);
    let err = |options: RenderOptions, mesh: &Mesh| render(mesh, &options).unwrap_err().to_string();
    assert!(err(RenderOptions { width: 0, ..small(Mode::Faces) }, &mesh).contains("picture size"));
    assert!(err(RenderOptions { samples: 9, ..small(Mode::Faces) }, &mesh).contains("samples"));
    let scalar = RenderOptions { colors: ColorSource::Scalar("k9".into()), ..small(Mode::Faces) };
    assert!(err(scalar, &mesh).contains("k9"));
    assert!(err(small(Mode::Faces), &Mesh::new(mesh.positions.clone(), vec![])).contains("no faces"));
    let mut bad = mesh.clone();
    bad.positions[3].x = f64::NAN;
    assert!(err(small(Mode::Faces), &bad).contains("vertex 3"));
}

#[test]
fn hillshade_lights_slopes_facing_the_north_west() {
    // A ridge along y = x: the north-west flank (x < y) faces the sun.
    let n = 65;
    let heights: Vec<f64> = (0..n * n).map(|i| -((i % n) as f64 - (i / n) as f64).abs() * 0.5).collect();
    let relief = Relief { heights: &heights, columns: n, spacing: (1.0, 1.0), exaggeration: Some(1.0) };
    let picture = hillshade(&relief, |_| [200, 200, 200]);
    // Row 0 of the picture is the north (largest y).
    let (north_west, south_east) = (picture.pixel(10, 20), picture.pixel(50, 40));
    assert!(north_west[0] > south_east[0] + 40, "{north_west:?} vs {south_east:?}");
}

#[test]
fn the_cli_renders_every_shared_mesh_and_terrain_previews() {
    let tmp = temp_dir();
    let run = |args: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_asperity"))
            .args(args)
            .current_dir(tmp.path())
            .output()
            .unwrap();
        assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
        out
    };
    for (i, file) in shared_mesh_files().iter().enumerate() {
        let png = format!("mesh-{i}.png");
        run(&[
            "render",
            file.to_str().unwrap(),
            "-o",
            &png,
            "--size",
            "96,72",
            "--mode",
            ["faces", "wireframe", "points"][i % 3],
        ]);
        let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(tmp.path().join(&png)).unwrap()));
        let info = decoder.read_info().unwrap().info().clone();
        assert_eq!((info.width, info.height), (96, 72), "{}", file.display());
    }
    let out = run(&["terrain", "--size", "65", "--seed", "3", "-o", "t.ply", "--preview", "t.png", "--json"]);
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["preview"], "t.png");
    assert!(tmp.path().join("t.png").is_file());
    run(&["terrain", "--method", "dual", "--levels", "4", "-o", "d.ply", "--preview", "d.png", "--quiet"]);
    assert!(tmp.path().join("d.png").is_file());
    // A picture needs a .png name; nothing is written otherwise.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_asperity"))
        .args(["render", "d.ply", "-o", "d.jpg"])
        .current_dir(tmp.path())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(!tmp.path().join("d.jpg").exists());
}

#[test]
fn a_mesh_that_covers_no_pixel_is_refused_and_huge_ones_are_drawn() {
    // #24 item 10: a mesh the camera cannot frame used to give a blank PNG with exit 0.
    let collapsed = Mesh::new(vec![DVec3::splat(2.0); 3], vec![[0, 1, 2]]);
    let err = render(&collapsed, &small(Mode::Faces)).unwrap_err();
    assert!(err.to_string().contains("nothing to draw"), "{err}");
    // Coordinates of 1e300 are drawn as their unit-size image is.
    let mut huge = icosphere(1.0, 3);
    huge.positions.iter_mut().for_each(|p| *p *= 1e300);
    let (a, b) =
        (render(&huge, &small(Mode::Faces)).unwrap(), render(&icosphere(1.0, 3), &small(Mode::Faces)).unwrap());
    assert_eq!(a.pixel(80, 60), b.pixel(80, 60));
}
