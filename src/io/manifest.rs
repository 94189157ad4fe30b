//! What the job-runner plans share (terrain tiles, #23; mesh chunks, #40): FNV-1a
//! fingerprints that do not change between builds, and reading a plan's `plan.json` with
//! its layout version checked.

use std::path::Path;

use serde::de::DeserializeOwned;

use crate::error::{Error, Result};

/// FNV-1a's 64-bit offset basis: the hash of no bytes.
pub const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

/// FNV-1a, 64 bits, of `bytes` continued from `hash` (start from [`FNV_OFFSET`]).
pub fn fnv1a(hash: u64, bytes: &[u8]) -> u64 {
    bytes.iter().fold(hash, |h, &b| (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3))
}

/// The fingerprint of `text`: its FNV-1a hash as 16 hex digits.
pub fn fingerprint(text: &str) -> String {
    format!("{:016x}", fnv1a(FNV_OFFSET, text.as_bytes()))
}

/// The plan in `dir` (a `kind` plan: "terrain", "simplify"), read from its `plan.json`,
/// whose layout version `version_of` gives and must be `version`.
///
/// # Errors
/// No manifest, not a plan of that kind, or a plan of another layout version.
pub fn read_plan<T: DeserializeOwned>(
    dir: &Path,
    kind: &str,
    version: u32,
    version_of: impl Fn(&T) -> u32,
) -> Result<T> {
    let manifest = dir.join("plan.json");
    let text = std::fs::read_to_string(&manifest).map_err(|e| Error::io(&manifest, e))?;
    let plan: T = serde_json::from_str(&text)
        .map_err(|e| Error::InvalidInput(format!("{}: not an asperity {kind} plan: {e}", manifest.display())))?;
    let found = version_of(&plan);
    if found != version {
        return Err(Error::InvalidInput(format!(
            "{}: plan version {found} (this asperity reads version {version}): make the plan again",
            manifest.display()
        )));
    }
    Ok(plan)
}
