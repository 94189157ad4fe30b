//! Process-wide memory settings for long runs over large meshes.
//!
//! glibc serves allocations above its mmap threshold with fresh mappings and gives them
//! back on free, but the threshold is dynamic: freeing a mapped block raises it to that
//! block's size (up to 32 MiB). After the first large buffer is freed, every later
//! per-level buffer of a hierarchy build (faces, the guard's grid, a level's plans) comes
//! from the heap, where freed memory stays resident: on a 1.31 M-triangle build the peak
//! grows by about a sixth. Pinning the threshold keeps it where it started.

/// The mmap threshold [`return_large_buffers_to_the_os`] pins: 1 MiB.
pub const MMAP_THRESHOLD: usize = 1 << 20;

/// Pins glibc's mmap threshold at [`MMAP_THRESHOLD`], so buffers of 1 MiB and more go
/// back to the operating system when freed. The `asperity` binary and the benchmarks call
/// it at start; programs embedding the library may call it too (it affects the whole
/// process). Returns false where it does nothing (not glibc, or glibc refused).
pub fn return_large_buffers_to_the_os() -> bool {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        // SAFETY: mallopt only changes allocator parameters; M_MMAP_THRESHOLD takes a
        // byte count, and 1 MiB is within its range (at most 32 MiB on 64-bit).
        #[allow(unsafe_code)]
        let accepted = unsafe { libc::mallopt(libc::M_MMAP_THRESHOLD, MMAP_THRESHOLD as libc::c_int) };
        accepted == 1
    }
    #[cfg(not(all(target_os = "linux", target_env = "gnu")))]
    {
        false
    }
}

/// Gives the allocator's free pages back to the operating system (glibc's `malloc_trim`,
/// over every arena). Returns whether anything was released.
pub fn trim() -> bool {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        // SAFETY: malloc_trim only walks the allocator's own free lists.
        #[allow(unsafe_code)]
        let released = unsafe { libc::malloc_trim(0) };
        released == 1
    }
    #[cfg(not(all(target_os = "linux", target_env = "gnu")))]
    {
        false
    }
}

/// The memory this process may still allocate, as far as the system tells: the least of
/// the kernel's available memory (`MemAvailable`), the room left under the cgroup's limit
/// (v2 `memory.max`, v1 `memory.limit_in_bytes`) and under the address-space limit
/// (`RLIMIT_AS`, less the current virtual size). `None` where nothing can be read.
pub fn available_bytes() -> Option<u64> {
    let mut limits: Vec<u64> = Vec::new();
    limits.extend(kib_field("/proc/meminfo", "MemAvailable:"));
    let cgroup_v2 = read_number(CGROUP_V2_MAX).map(|max| max.saturating_sub(read_number(CGROUP_V2_USED).unwrap_or(0)));
    let cgroup_v1 = read_number(CGROUP_V1_MAX).map(|max| max.saturating_sub(read_number(CGROUP_V1_USED).unwrap_or(0)));
    limits.extend(cgroup_v2.or(cgroup_v1));
    let mut rlimit = libc::rlimit { rlim_cur: 0, rlim_max: 0 };
    // SAFETY: getrlimit writes one rlimit struct, which lives on this stack frame.
    #[allow(unsafe_code)]
    let ok = unsafe { libc::getrlimit(libc::RLIMIT_AS, &mut rlimit) } == 0;
    if ok && rlimit.rlim_cur != libc::RLIM_INFINITY {
        let used = kib_field("/proc/self/status", "VmSize:").unwrap_or(0);
        let allowed: u64 = rlimit.rlim_cur;
        limits.push(allowed.saturating_sub(used));
    }
    limits.into_iter().min()
}

/// The cgroup's limit and use (v2, then v1).
const CGROUP_V2_MAX: &str = "/sys/fs/cgroup/memory.max";
const CGROUP_V2_USED: &str = "/sys/fs/cgroup/memory.current";
const CGROUP_V1_MAX: &str = "/sys/fs/cgroup/memory/memory.limit_in_bytes";
const CGROUP_V1_USED: &str = "/sys/fs/cgroup/memory/memory.usage_in_bytes";

/// A `/proc` file's `key` field given in kB, in bytes.
fn kib_field(path: &str, key: &str) -> Option<u64> {
    let text = std::fs::read_to_string(path).ok()?;
    let line = text.lines().find(|l| l.starts_with(key))?;
    line.split_whitespace().nth(1)?.parse::<u64>().ok().map(|kib| kib * 1024)
}

/// A file holding one number (a cgroup setting); `None` for "max" or no such file.
fn read_number(path: &str) -> Option<u64> {
    std::fs::read_to_string(path).ok()?.trim().parse().ok()
}

/// The process's memory budget in bytes (0: not set, see [`budget`]).
static BUDGET: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// The share of the machine's memory (its total, or the cgroup's limit) the budget is by
/// default: three quarters, leaving room for the system and for what estimates miss.
pub const DEFAULT_BUDGET_SHARE: f64 = 0.75;

/// Sets the process's memory budget (the command line's `--max-memory`); `None` restores
/// the default, [`DEFAULT_BUDGET_SHARE`] of the machine's memory. Every estimate
/// ([`ensure_available`]) is checked against it as well as against what is available.
pub fn set_budget(bytes: Option<u64>) {
    BUDGET.store(bytes.unwrap_or(0), std::sync::atomic::Ordering::Relaxed);
}

/// The budget set by [`set_budget`], or by default [`DEFAULT_BUDGET_SHARE`] of the machine's
/// memory (`MemTotal`, or the cgroup's limit when lower); `None` where neither can be read.
pub fn budget() -> Option<u64> {
    match BUDGET.load(std::sync::atomic::Ordering::Relaxed) {
        0 => machine_bytes().map(|total| (total as f64 * DEFAULT_BUDGET_SHARE) as u64),
        set => Some(set),
    }
}

/// Whether a budget was set ([`set_budget`]), rather than the default share.
pub fn budget_is_set() -> bool {
    BUDGET.load(std::sync::atomic::Ordering::Relaxed) != 0
}

/// The machine's memory: `MemTotal`, or the cgroup's limit when lower.
fn machine_bytes() -> Option<u64> {
    let total = kib_field("/proc/meminfo", "MemTotal:")?;
    let cgroup = read_number(CGROUP_V2_MAX).or_else(|| read_number(CGROUP_V1_MAX));
    Some(cgroup.map_or(total, |c| c.min(total)))
}

/// Refuses work that needs more memory than [`available_bytes`] says there is, or more than
/// the [`budget`], before anything is allocated: `what` and `advice` make the one-line
/// message.
///
/// # Errors
/// [`crate::Error::InvalidInput`] saying how much is needed and what it exceeds.
pub fn ensure_available(needed: u64, what: &str, advice: &str) -> crate::Result<()> {
    if let Some(budget) = budget().filter(|&b| needed > b) {
        let source = if !budget_is_set() {
            format!(
                "the memory budget of {} ({:.0} % of this machine's; --max-memory sets it)",
                human_bytes(budget),
                DEFAULT_BUDGET_SHARE * 100.0
            )
        } else {
            format!("the --max-memory budget of {}", human_bytes(budget))
        };
        return Err(crate::Error::InvalidInput(format!(
            "{what} needs about {} in memory, more than {source}: {advice}",
            human_bytes(needed)
        )));
    }
    match available_bytes() {
        Some(available) if needed > available => Err(crate::Error::InvalidInput(format!(
            "{what} needs about {} in memory, more than the {} available: {advice}",
            human_bytes(needed),
            human_bytes(available)
        ))),
        _ => Ok(()),
    }
}

/// A byte count as people write it: `1500000`, `512M`, `2G`, `1.5GB`, `64KiB` (K, M, G, T
/// are powers of 1024, with or without `B` or `iB`).
///
/// # Errors
/// A message saying what is wrong.
pub fn parse_size(text: &str) -> std::result::Result<u64, String> {
    let trimmed = text.trim();
    let split = trimmed.find(|c: char| !(c.is_ascii_digit() || c == '.')).unwrap_or(trimmed.len());
    let (number, unit) = trimmed.split_at(split);
    let number: f64 = number.parse().map_err(|_| format!("`{text}` is not a size (e.g. 512M, 2G)"))?;
    let unit = unit.trim().to_ascii_uppercase();
    let unit = unit.trim_end_matches("IB").trim_end_matches('B');
    let scale: f64 = match unit {
        "" => 1.0,
        "K" => 1024.0,
        "M" => 1024.0 * 1024.0,
        "G" => 1024.0 * 1024.0 * 1024.0,
        "T" => 1024.0 * 1024.0 * 1024.0 * 1024.0,
        _ => return Err(format!("`{text}`: unknown unit (K, M, G or T)")),
    };
    let bytes = number * scale;
    if !(1.0..1.8e19).contains(&bytes) {
        return Err(format!("`{text}` must be at least one byte"));
    }
    Ok(bytes as u64)
}

fn human_bytes(bytes: u64) -> String {
    // Binary units, as --max-memory reads them.
    let b = bytes as f64;
    match bytes {
        0..=1_048_575 => format!("{:.1} KiB", b / 1024.0),
        1_048_576..=1_073_741_823 => format!("{:.1} MiB", b / 1_048_576.0),
        _ => format!("{:.1} GiB", b / 1_073_741_824.0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_read_as_people_write_them() {
        assert_eq!(parse_size("1500000"), Ok(1_500_000));
        assert_eq!(parse_size("512M"), Ok(512 << 20));
        assert_eq!(parse_size("2G"), Ok(2 << 30));
        assert_eq!(parse_size("1.5GB"), Ok(3 << 29));
        assert_eq!(parse_size("64KiB"), Ok(64 << 10));
        assert!(parse_size("0").is_err());
        assert!(parse_size("2X").is_err());
        assert!(parse_size("lots").is_err());
    }
}
