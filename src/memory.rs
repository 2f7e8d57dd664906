//! The process's allocator settings for training and batched inference (native builds on glibc).
//!
//! A training step frees and reallocates hundreds of activation buffers of a few megabytes. glibc's
//! malloc serves allocations above its mmap threshold with fresh `mmap`s and hands them back on
//! `free` (and trims the heap top above its trim threshold), so every step faults the same memory
//! in again and the kernel zeroes it page by page: on flex that was ~20 % of a stylizer step's CPU
//! time in `clear_page`/page faults (bench/README.md). [`keep_freed_memory`] raises both
//! thresholds so freed buffers stay in the heap for the next step.

/// Keeps freed memory in the process for reuse (glibc: `M_MMAP_THRESHOLD` 32 MiB, its maximum,
/// and `M_TRIM_THRESHOLD` 1 GiB). Call once at start-up, before the work; a no-op elsewhere
/// (other C libraries, wasm). Peak memory is unchanged; the process keeps what it freed until it
/// exits.
pub fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        // glibc's <malloc.h>.
        const M_TRIM_THRESHOLD: std::os::raw::c_int = -1;
        const M_MMAP_THRESHOLD: std::os::raw::c_int = -3;
        unsafe extern "C" {
            fn mallopt(param: std::os::raw::c_int, value: std::os::raw::c_int) -> std::os::raw::c_int;
        }
        // SAFETY: mallopt only changes malloc's tuning parameters; it is thread-safe and takes
        // plain integers. A rejected value (return 0) leaves the default in place.
        unsafe {
            mallopt(M_MMAP_THRESHOLD, 32 << 20);
            mallopt(M_TRIM_THRESHOLD, 1 << 30);
        }
    }
}
