//! `asperity menger --level N -o OUT`: the Menger sponge as one closed mesh.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use crate::error::Result;
use crate::io::WriteOptions;
use crate::scene::menger::MengerRequest;

/// The subcommand's flags: the sponge's request and where it goes.
#[derive(Debug, Args)]
pub struct MengerArgs {
    #[command(flatten)]
    sponge: MengerRequest,
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
    let sponge = args.sponge.sponge()?;
    crate::io::write(&sponge, &args.output, WriteOptions { ascii: args.ascii })?;
    let report = sponge.validate();
    ctx.report(
        || {
            format!(
                "menger: level {} => {} vertices, {} tris, genus {} => {} in {} ms",
                args.sponge.level,
                sponge.vertex_count(),
                sponge.face_count(),
                report.genus.map_or("-".into(), |g| g.to_string()),
                args.output.display(),
                super::super::millis(start)
            )
        },
        || {
            serde_json::json!({
                "output": args.output, "level": args.sponge.level, "edge": args.sponge.edge, "vertices": sponge.vertex_count(),
                "triangles": sponge.face_count(), "genus": report.genus, "closed": report.is_closed_manifold(),
                "seconds": start.elapsed().as_secs_f64(),
            })
        },
    );
    Ok(())
}
