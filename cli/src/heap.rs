//! How the C library's allocator grows its heaps, set for the commands
//! that render before any thread starts.
//!
//! glibc gives each thread that allocates an arena of its own and grows
//! that arena's heap one `mprotect` call at a time, by exactly what the
//! allocation at hand lacks. A one-image render of the bunny
//! (`spatch render bunny.spatch -o out.png --threads 2`) made 2,893 such
//! calls from its pool threads (`strace -f -c`), and the two threads
//! waited on each other's calls for the process's memory map. A top pad
//! makes a new heap readable and writable up to its 64 MiB maximum in one
//! call, and the main heap grow in steps of the pad. Pages are still only
//! backed by memory when first written. Measured: the bunny's one-image
//! command 26.1 → 24.4 ms (medians of 21 alternated runs, `GLIBC_TUNABLES`
//! with the same pad), its `--bench` frame unchanged.
//!
//! Why only `render` and `eval`: with the pad an arena keeps up to 64 MiB
//! of freed memory instead of returning it, and the converters' peak
//! memory (docs/scale.md) is measured with the allocator's defaults.

/// The top pad: glibc's largest heap of a thread's arena on 64-bit
/// systems, so a new arena's heap is made usable in one step.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
const TOP_PAD: libc::c_int = 64 << 20;

/// Sets the allocator's top pad ([`TOP_PAD`]); call it in `main` before
/// any thread starts. Other C libraries keep their defaults.
pub(crate) fn pad_heaps() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: `mallopt` only changes a tuning value of glibc's allocator;
    // called before any other thread exists, it races with nothing. A
    // refusal (return value 0) leaves the default, which is correct too.
    #[allow(unsafe_code)]
    unsafe {
        libc::mallopt(libc::M_TOP_PAD, TOP_PAD);
    }
}
