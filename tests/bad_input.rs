//! Malformed files give `Error::Parse` naming the file and where, never a panic, and
//! absurd counts are refused before anything large is allocated.

use asperity::io;
use asperity::{Error, Location};

use crate::common::temp_dir;

/// A bad file: its name, its bytes, where the error must point and a phrase of the message.
struct Case {
    name: &'static str,
    bytes: Vec<u8>,
    at: Location,
    says: &'static str,
}

fn case(name: &'static str, text: &str, at: Location, says: &'static str) -> Case {
    Case { name, bytes: text.as_bytes().to_vec(), at, says }
}

fn binary_ply(header_count: &str, body: &[u8]) -> Vec<u8> {
    let mut bytes = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {header_count}\nproperty float x\nproperty float y\nproperty float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n"
    )
    .into_bytes();
    bytes.extend_from_slice(body);
    bytes
}

fn cases() -> Vec<Case> {
    use Location::{Byte, File, Line};
    let ply_ascii = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    vec![
        case("truncated.off", "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n", Line(5), "ends after 3 of 8 vertices"),
        case("few-faces.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", Line(6), "ends after 1 of 2 faces"),
        case("nan.off", "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n", Line(4), "not finite"),
        case("inf.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 inf 0\n3 0 1 2\n", Line(5), "not finite"),
        case("range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", Line(6), "out of range"),
        case("repeat.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 1\n", Line(6), "repeats vertex 1"),
        case("short-face.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n", Line(6), "declares 4 corners"),
        case("huge.off", "OFF\n900000000000 1 0\n0 0 0\n", Line(3), "ends after 1 of 900000000000 vertices"),
        case("not-off.off", "PLY\n3 1 0\n", Line(1), "expected the OFF keyword"),
        case("words.off", "OFF\n3 1 0\n0 0 zero\n1 0 0\n0 1 0\n3 0 1 2\n", Line(3), "`zero` is not a number"),
        Case { name: "garbage.off", bytes: vec![0xff, 0xfe, 0x00, 0x9c, 0x80], at: Byte(0), says: "not a text file" },
        case("empty.off", "", File, "empty"),
        case("empty.ply", "", File, "empty"),
        case("empty.stl", "", File, "empty"),
        case("empty.obj", "", File, "empty"),
        case(
            "unknown-type.ply",
            "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n",
            Line(4),
            "unknown PLY type `quad`",
        ),
        case("no-end.ply", "ply\nformat ascii 1.0\nelement vertex 1\n", File, "end_header"),
        case("bad-format.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n", Line(2), "unknown PLY format"),
        case("trunc.ply", &format!("{ply_ascii}0 0 0\n1 0 0\n"), Line(11), "vertex 2: the file ends early"),
        case("range.ply", &format!("{ply_ascii}0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"), Line(13), "out of range"),
        case("inf.ply", &format!("{ply_ascii}0 0 0\n1 0 inf\n0 1 0\n3 0 1 2\n"), Line(11), "not finite"),
        case(
            "noxyz.ply",
            "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n",
            Line(3),
            "lack x, y and z",
        ),
        Case {
            name: "huge.ply",
            bytes: binary_ply("4000000000", &[0; 24]),
            at: Line(3),
            says: "declares 4000000000 vertex elements",
        },
        Case {
            name: "trunc-bin.ply",
            bytes: binary_ply("2", &[0; 20]),
            at: Line(3),
            says: "declares 2 vertex elements",
        },
        case("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", Line(4), "out of bounds"),
        case("words.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n", Line(2), "position parse error"),
        case("nan.obj", "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n", Line(3), "not finite"),
        case("repeat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 2\n", Line(5), "repeats vertex"),
        case(
            "trunc.stl",
            "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n",
            Line(5),
            "ends before `vertex`",
        ),
        case(
            "quad.stl",
            "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n",
            Line(7),
            "expected `endloop`",
        ),
        Case {
            name: "wrong-count.stl",
            bytes: {
                let mut b = vec![0u8; 80];
                b.extend(1_000_000u32.to_le_bytes());
                b.extend([0u8; 50]);
                b
            },
            at: Byte(80),
            says: "declares 1000000 facets",
        },
        case("unknown.xyz", "1 2 3\n", File, "unknown mesh format"),
    ]
}

#[test]
fn every_bad_file_is_a_located_parse_error() {
    let dir = temp_dir();
    for c in cases() {
        let path = dir.path().join(c.name);
        std::fs::write(&path, &c.bytes).unwrap();
        match io::read(&path) {
            Err(e @ Error::Parse { .. }) => {
                let Error::Parse { path: p, at, msg } = &e else { unreachable!() };
                assert_eq!(p, &path, "{}", c.name);
                assert_eq!(at, &c.at, "{}: {e}", c.name);
                assert!(msg.contains(c.says), "{}: `{msg}` should say `{}`", c.name, c.says);
                let shown = e.to_string();
                assert!(shown.contains(c.name) && !shown.contains('\n'), "{shown}");
                assert_eq!(e.exit_code(), 2);
            }
            other => panic!("{}: expected a parse error, got {other:?}", c.name),
        }
    }
}

#[test]
fn a_missing_file_is_an_io_error_naming_it() {
    let err = io::read(std::path::Path::new("/nonexistent/mesh.off")).unwrap_err();
    assert!(matches!(err, Error::Io { .. }));
    assert!(err.to_string().contains("/nonexistent/mesh.off"));
    assert_eq!(err.exit_code(), 2);
}
