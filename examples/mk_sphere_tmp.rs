use asperity::mesh::primitives::icosphere;
use asperity::noise::{Frame, NoiseField, NoiseKind, NoiseSpec};
use glam::DVec3;
fn main() {
    let level: u32 = std::env::args().nth(1).unwrap().parse().unwrap();
    let out = std::env::args().nth(2).unwrap();
    let mut mesh = icosphere(1.0, level);
    let field = NoiseField::new(&NoiseSpec { kind: NoiseKind::Fbm, seed: 7, ..NoiseSpec::default() }).expect("fbm");
    let frame = Frame { tangent: DVec3::X, bitangent: DVec3::Y };
    for p in &mut mesh.positions {
        let n = p.normalize();
        *p = n * (1.0 + 0.08 * field.sample3(n * 4.0, frame));
    }
    asperity::io::write(&mesh, std::path::Path::new(&out), Default::default()).unwrap();
}
