//! The clock runs are timed with.

use std::sync::OnceLock;

/// CPU time of the calling thread (s): `clock_gettime(CLOCK_THREAD_CPUTIME_ID)`.
/// The simulations run on the calling thread and start no others, so this
/// is the process CPU time of the simulation, without the time of any other
/// thread (the progress display). On targets without that clock
/// (non-Unix), wall time since the first call.
pub fn thread_cpu_seconds() -> f64 {
    #[cfg(unix)]
    {
        let mut ts = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: `ts` is a valid, writable timespec; the clock id is a
        // constant the platform defines.
        let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
        if rc == 0 {
            return ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9;
        }
    }
    static START: OnceLock<std::time::Instant> = OnceLock::new();
    START
        .get_or_init(std::time::Instant::now)
        .elapsed()
        .as_secs_f64()
}

/// The clock [`thread_cpu_seconds`] reads, in words.
pub fn clock_name() -> &'static str {
    if cfg!(unix) {
        "thread CPU time (clock_gettime(CLOCK_THREAD_CPUTIME_ID))"
    } else {
        "wall time (no thread CPU clock on this platform)"
    }
}
