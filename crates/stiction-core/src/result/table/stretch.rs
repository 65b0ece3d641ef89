//! How the table's rows are shared out over threads, and the memory they are written into:
//! one stretch of rows per thread, the calling thread's among them (`share`), written into a
//! table that is not zeroed first; a large one is written past the caches, and its memory
//! reused by the next.

use std::mem::MaybeUninit;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, PoisonError};
use std::time::{Duration, Instant};

use crate::result::SimResult;

/// Rows per stretch: one stretch per thread of the pool (the calling thread counted as one),
/// and never fewer than `fewest`. Four per thread, so that a pool thread waking late would still
/// find stretches to take, measured better in the core alone but worse from Python
/// (CoupledClutches' table 0.383 → 0.427 ms, SimpleGearShift's 0.146 → 0.160, alternating
/// processes): each stretch's last partial block and hand-over cost more than the balance won.
pub(super) fn stretch_rows(rows: usize, fewest: usize) -> usize {
    rows.div_ceil(rayon::current_num_threads()).max(fewest)
}

/// How long the calling thread waits awake for the stretches the pool's threads still compute
/// before it sleeps: a sleeping thread took 50–60 µs to wake on this 2-core VM.
pub(super) const WAIT_AWAKE: Duration = Duration::from_micros(200);

/// Runs `fill` on every stretch, on this thread and on the pool's threads, each taking the
/// next stretch not yet taken, with a context of its own (`context`, made once per thread and
/// kept from one stretch to the next). The calling thread starts at once and never waits asleep
/// for a stretch nobody has started (it takes it itself); for those the pool's threads are still
/// computing, it waits awake (`WAIT_AWAKE`). Rayon's `par_chunks_mut` puts the calling thread to
/// sleep and wakes it at the end, and a pool thread woken late left a stretch for after the
/// other: CoupledClutches' table 0.43 ms (90th percentile 0.79) that way, 0.38 (0.47) this way.
pub(super) fn share<T: Send, C>(
    stretches: Vec<T>,
    context: impl Fn() -> C + Sync,
    fill: impl Fn(&mut C, T) + Sync,
) {
    let count = stretches.len();
    let left = Mutex::new(stretches);
    // Threads inside `take`. Once the caller's own `take` returns, every stretch is done or
    // being computed by a thread counted here; a thread leaves once it has dropped its context
    // too, so the caller waits awake for that as well, not only for the stretches.
    let busy = AtomicUsize::new(0);
    let take = || {
        busy.fetch_add(1, Ordering::AcqRel);
        let mut own = None;
        loop {
            let next = left.lock().unwrap_or_else(PoisonError::into_inner).pop();
            let Some(stretch) = next else { break };
            fill(own.get_or_insert_with(&context), stretch);
        }
        drop(own);
        busy.fetch_sub(1, Ordering::Release);
    };
    rayon::in_place_scope(|scope| {
        for _ in 1..count.min(rayon::current_num_threads()) {
            scope.spawn(|_| take());
        }
        take();
        let start = Instant::now();
        while busy.load(Ordering::Acquire) > 0 && start.elapsed() < WAIT_AWAKE {
            std::hint::spin_loop();
        }
        // leaving the scope waits (asleep) for the rest
    });
}

/// The table rows of one stretch: `data` holds rows `first..`, `width` values each, not yet
/// written; `written` counts the cells written so far; `stream`: written past the caches
/// (`streams`).
pub(super) struct Stretch<'a> {
    pub data: &'a mut [MaybeUninit<f64>],
    pub first: usize,
    pub width: usize,
    pub written: usize,
    pub stream: bool,
}

impl<'a> Stretch<'a> {
    /// Rows `first..` of a table `width` values wide, none written yet, in `data`.
    pub(super) fn new(
        data: &'a mut [MaybeUninit<f64>],
        first: usize,
        width: usize,
        stream: bool,
    ) -> Self {
        Self {
            data,
            first,
            width,
            written: 0,
            stream,
        }
    }
}

/// Tables from this size (bytes) on are written past the caches: far larger than them, they
/// would only push out what the evaluation keeps there, and a store that bypasses them does
/// not first read each line from memory. HeatLosses' 35 MB table: 7.5 → 6.4 ms.
const STREAM_FROM: usize = 16 << 20;

/// Whether a table of `cells` values is written past the caches.
pub(super) fn streams(cells: usize) -> bool {
    cells * size_of::<f64>() >= STREAM_FROM
}

/// Writes one cell, past the caches when `STREAM`.
#[inline(always)]
pub(super) fn put<const STREAM: bool>(cell: &mut MaybeUninit<f64>, value: f64) {
    #[cfg(target_arch = "x86_64")]
    if STREAM {
        // SAFETY: `cell` is valid for an aligned 8-byte write; SSE2 (MOVNTI) is part of x86-64.
        unsafe {
            std::arch::x86_64::_mm_stream_si64(cell.as_mut_ptr().cast(), value.to_bits() as i64)
        };
        return;
    }
    cell.write(value);
}

/// Orders this thread's streamed cells before anything it does next (handing the stretch back
/// to the thread that reads the table): such stores are not ordered by the usual fences.
pub(super) fn settle(stretch: &Stretch) {
    #[cfg(target_arch = "x86_64")]
    if stretch.stream {
        // SAFETY: SFENCE has no operands and is part of x86-64.
        unsafe { std::arch::x86_64::_mm_sfence() };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = stretch; // plain stores elsewhere: nothing to order
}

/// Tables from this size (bytes) on get memory fresh from the kernel, which clears every page
/// first (glibc maps blocks above 32 MB anew and unmaps them when freed): a fifth of
/// HeatLosses' run and table went into clearing pages. Such a table's memory is kept, once
/// it is no longer used, for the next table of about its size.
const RECYCLE_FROM: usize = 32 << 20;
/// The largest memory kept (bytes): what stays allocated after every result is gone.
const RECYCLE_UP_TO: usize = 256 << 20;

/// The memory of the last large table no longer used (empty: none).
static KEPT: Mutex<Vec<f64>> = Mutex::new(Vec::new());

/// Memory for a table of `cells` values: the kept memory if it fits (its old values are not
/// cleared: every cell is written), else fresh memory. (Advising fresh memory onto huge pages,
/// as the seventh round did, made it dearer where results are kept: forty HeatLosses tables
/// kept took 2.5 s instead of 1.1 s, the kernel compacting memory for the huge pages.)
pub(super) fn table_memory(cells: usize) -> Vec<f64> {
    // at most twice what is needed (the kept memory is at least 32 MB: a small table never
    // takes it)
    let mut kept = KEPT.lock().unwrap_or_else(PoisonError::into_inner);
    if (cells..=2 * cells).contains(&kept.capacity()) {
        let mut data = std::mem::take(&mut *kept);
        data.clear();
        return data;
    }
    Vec::with_capacity(cells)
}

/// Keeps the memory of a table no longer used for the next one (the newest: the next table
/// is most likely the same model's), if it is large.
pub fn recycle_table(data: Vec<f64>) {
    let bytes = data.capacity() * size_of::<f64>();
    if (RECYCLE_FROM..=RECYCLE_UP_TO).contains(&bytes) {
        let old = std::mem::replace(
            &mut *KEPT.lock().unwrap_or_else(PoisonError::into_inner),
            data,
        );
        drop(old); // after the lock: unmapping takes a while
    }
}

/// A large table's memory goes to the next table.
impl Drop for SimResult {
    fn drop(&mut self) {
        if let Some(table) = self.table.take() {
            recycle_table(table);
        }
        let ready = self.ready.get_mut().unwrap_or_else(PoisonError::into_inner);
        if let Some(table) = ready.take() {
            recycle_table(table);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{recycle_table, streams};
    use crate::ModelSpec;

    /// A large table written into kept memory full of other values is the table written into
    /// fresh memory, bit for bit (every cell written, past the caches), and the kept memory is
    /// what it was written into.
    #[test]
    fn kept_memory_gives_the_same_table() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/msl");
        let text = std::fs::read_to_string(format!("{dir}/HeatLosses.toml")).expect("example");
        let spec = ModelSpec::from_toml(&text, dir).expect("valid model");
        let r = crate::simulate(&spec).expect("runs");
        let fresh = r.compute_table();
        assert!(
            streams(fresh.len()),
            "a table this large is written past the caches"
        );
        let old = vec![-1.5; fresh.len()];
        let at = old.as_ptr();
        recycle_table(old);
        let again = r.compute_table();
        assert_eq!(again.as_ptr(), at, "the kept memory is reused");
        let same = fresh
            .iter()
            .zip(&again)
            .all(|(a, b)| a.to_bits() == b.to_bits());
        assert!(same && fresh.len() == again.len(), "the tables differ");
    }
}
