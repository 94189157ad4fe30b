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

/// The memory this process may still allocate, as far as the system tells: the least of
/// the kernel's available memory (`MemAvailable`), the room left under the cgroup's limit
/// (v2 `memory.max`, v1 `memory.limit_in_bytes`) and under the address-space limit
/// (`RLIMIT_AS`, less the current virtual size). `None` where nothing can be read.
pub fn available_bytes() -> Option<u64> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok();
    let field = |text: &str, key: &str| -> Option<u64> {
        let line = text.lines().find(|l| l.starts_with(key))?;
        line.split_whitespace().nth(1)?.parse::<u64>().ok().map(|kib| kib * 1024)
    };
    let read_number = |path: &str| -> Option<u64> { std::fs::read_to_string(path).ok()?.trim().parse().ok() };
    let mut limits: Vec<u64> = Vec::new();
    limits.extend(meminfo.as_deref().and_then(|m| field(m, "MemAvailable:")));
    let cgroup_v2 = read_number("/sys/fs/cgroup/memory.max")
        .map(|max| max.saturating_sub(read_number("/sys/fs/cgroup/memory.current").unwrap_or(0)));
    let cgroup_v1 = read_number("/sys/fs/cgroup/memory/memory.limit_in_bytes")
        .map(|max| max.saturating_sub(read_number("/sys/fs/cgroup/memory/memory.usage_in_bytes").unwrap_or(0)));
    limits.extend(cgroup_v2.or(cgroup_v1));
    let mut rlimit = libc::rlimit { rlim_cur: 0, rlim_max: 0 };
    // SAFETY: getrlimit writes one rlimit struct, which lives on this stack frame.
    #[allow(unsafe_code)]
    let ok = unsafe { libc::getrlimit(libc::RLIMIT_AS, &mut rlimit) } == 0;
    if ok && rlimit.rlim_cur != libc::RLIM_INFINITY {
        let status = std::fs::read_to_string("/proc/self/status").ok();
        let used = status.as_deref().and_then(|s| field(s, "VmSize:")).unwrap_or(0);
        let allowed: u64 = rlimit.rlim_cur;
        limits.push(allowed.saturating_sub(used));
    }
    limits.into_iter().min()
}

/// Refuses work that needs more memory than [`available_bytes`] says there is, before
/// anything is allocated: `what` and `advice` make the one-line message.
///
/// # Errors
/// [`crate::Error::InvalidInput`] saying how much is needed and available.
pub fn ensure_available(needed: u64, what: &str, advice: &str) -> crate::Result<()> {
    match available_bytes() {
        Some(available) if needed > available => Err(crate::Error::InvalidInput(format!(
            "{what} needs about {} in memory, more than the {} available: {advice}",
            gigabytes(needed),
            gigabytes(available)
        ))),
        _ => Ok(()),
    }
}

fn gigabytes(bytes: u64) -> String {
    format!("{:.1} GB", bytes as f64 / 1e9)
}
