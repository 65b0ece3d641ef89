//! How the table's rows are shared out over threads, and the memory they are written into:
//! one stretch of rows per thread, written into a table that is neither zeroed first nor, when
//! large, faulted in 4 KiB pages.

use std::mem::MaybeUninit;

/// Asks Linux to back a large table with huge pages: its memory is fresh from the kernel
/// (above glibc's 32 MB reuse limit), and faulting it in 4 KiB pages took about 8 700 faults
/// and 40 % of HeatLosses' table time. Only advice: where huge pages are off, nothing changes.
#[cfg(target_os = "linux")]
pub(super) fn advise_huge_pages(data: &mut Vec<f64>) {
    const HUGE: usize = 2 << 20;
    let (start, len) = (
        data.as_mut_ptr() as usize,
        data.capacity() * size_of::<f64>(),
    );
    let first = start.next_multiple_of(HUGE);
    let end = (start + len) / HUGE * HUGE;
    if end > first {
        // SAFETY: the range lies inside the vector's own allocation; MADV_HUGEPAGE changes
        // neither its contents nor its mapping, and its result (advice refused) is ignored.
        unsafe { libc::madvise(first as *mut libc::c_void, end - first, libc::MADV_HUGEPAGE) };
    }
}

#[cfg(not(target_os = "linux"))]
pub(super) fn advise_huge_pages(_: &mut Vec<f64>) {}

/// Rows per stretch computed on one thread: one stretch per thread (rows cost about the same,
/// and each stretch pays for a workspace, its modes' factors and a hand-over to the pool), and
/// never fewer than `fewest`.
pub(super) fn stretch_rows(rows: usize, fewest: usize) -> usize {
    rows.div_ceil(rayon::current_num_threads()).max(fewest)
}

/// The table rows of one stretch: `data` holds rows `first..`, `width` values each, not yet
/// written; `written` counts the cells written so far.
pub(super) struct Stretch<'a> {
    pub data: &'a mut [MaybeUninit<f64>],
    pub first: usize,
    pub width: usize,
    pub written: usize,
}
