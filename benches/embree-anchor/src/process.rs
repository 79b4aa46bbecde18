//! The process's resident memory (`/proc/self/statm`) and CPU time.

extern "C" {
    fn sysconf(name: i32) -> std::ffi::c_long;
    fn clock_gettime(clock: i32, ts: *mut Timespec) -> i32;
}

#[repr(C)]
struct Timespec {
    sec: i64,
    nsec: std::ffi::c_long,
}

/// `_SC_PAGESIZE` on Linux.
const SC_PAGESIZE: i32 = 30;
/// `CLOCK_PROCESS_CPUTIME_ID` on Linux.
const CLOCK_PROCESS_CPUTIME_ID: i32 = 2;

/// Resident bytes now (0 where `/proc` is unavailable).
#[must_use]
pub fn resident() -> u64 {
    let page = unsafe { sysconf(SC_PAGESIZE) }.max(1) as u64;
    std::fs::read_to_string("/proc/self/statm")
        .ok()
        .and_then(|s| s.split_whitespace().nth(1).and_then(|r| r.parse::<u64>().ok()))
        .map_or(0, |pages| pages * page)
}

/// CPU time of all the process's threads so far, ms: on a shared machine, what a frame
/// cost on the cores it got, free of the time it waited for them.
#[must_use]
pub fn cpu_ms() -> f64 {
    let mut ts = Timespec { sec: 0, nsec: 0 };
    unsafe { clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &raw mut ts) };
    ts.sec as f64 * 1e3 + ts.nsec as f64 * 1e-6
}
