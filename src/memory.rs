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
