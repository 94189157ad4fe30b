//! `asperity menger --level N -o OUT`: the Menger sponge as one closed mesh.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use crate::error::Result;
use crate::io::WriteOptions;
use crate::scene::menger::{MAX_LEVEL, menger_sponge};

/// The subcommand's flags.
#[derive(Debug, Args)]
pub struct MengerArgs {
    /// Recursion level (0 is the cube).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(0..=i64::from(MAX_LEVEL)))]
    level: u32,
    /// Edge length of the whole sponge, centred at the origin.
    #[arg(long, default_value_t = 1.0)]
    edge: f64,
    /// Output mesh; the format follows the extension.
    #[arg(short, long)]
    output: PathBuf,
    /// Write text PLY/STL instead of binary.
    #[arg(long)]
    ascii: bool,
}

/// Runs the subcommand.
pub fn run(args: MengerArgs, ctx: super::super::Context) -> Result<()> {
    let start = Instant::now();
    super::super::refuse_ascii_for(&args.output, args.ascii)?;
    let sponge = menger_sponge(args.level, args.edge)?;
    crate::io::write(&sponge, &args.output, WriteOptions { ascii: args.ascii })?;
    let report = sponge.validate();
    ctx.report(
        || {
            format!(
                "menger: level {} => {} vertices, {} tris, genus {} => {} in {} ms",
                args.level,
                sponge.vertex_count(),
                sponge.face_count(),
                report.genus.map_or("-".into(), |g| g.to_string()),
                args.output.display(),
                super::super::millis(start)
            )
        },
        || {
            serde_json::json!({
                "output": args.output, "level": args.level, "edge": args.edge, "vertices": sponge.vertex_count(),
                "triangles": sponge.face_count(), "genus": report.genus, "closed": report.is_closed_manifold(),
                "seconds": start.elapsed().as_secs_f64(),
            })
        },
    );
    Ok(())
}
