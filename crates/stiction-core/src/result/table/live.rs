//! The table of every variable computed while the run goes on. A run is sequential: on a
//! machine of two cores or more the others wait. Here the run hands the rows it recorded,
//! slice by slice (`Feed::send`), to the pool's threads, which evaluate them into the table
//! while the run integrates on; once the run ends, every thread takes rows left from its result
//! until none is. The values are those of the table computed after the run, bit for bit: each
//! row is evaluated by itself, from its own states and discrete state.

use std::collections::VecDeque;
use std::mem::MaybeUninit;
use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::time::Instant;

use super::block::{Block, BLOCK};
use super::rows::RowEvaluator;
use super::shape::Shape;
use super::stretch::{recycle_table, streams, stretch_rows, table_memory, Stretch, WAIT_AWAKE};
use super::{fill_stretch, kept_shape, Context, FEWEST_ROWS};
use crate::engine::eval::DiscreteState;
use crate::result::{SimResult, Trajectory};
use crate::system::System;

/// Rows a thread takes at a time: once the run ends, the threads share what is left in pieces
/// of this size.
const CHUNK: usize = 2 * BLOCK;

/// The most chunks waiting for the pool's threads: enough for one of them to stay busy from one
/// slice of the run to the next (HeatLosses computes a chunk in about 60 µs), few enough that
/// few rows are copied for nothing (rows not sent are computed after the run, uncopied).
const AHEAD: usize = 8;

/// The fewest rows a run is expected to record for its table to be computed while it goes on:
/// below, the table is computed after the run (SimpleGearShift's 1 012 rows: run and table in
/// 0.345 ms while it goes on, 0.32 ms after).
const LIVE_FROM: usize = 2048;

/// Rows recorded by the run, copied (the run's trajectory grows, and moves, as it goes on):
/// rows `first..` of the run, which refer to its discrete states by their index in the run.
struct Chunk {
    first: usize,
    rows: Trajectory,
}

/// What a thread computes next: a chunk the run sent, or rows of the ended run's result.
enum Work {
    Chunk(Chunk),
    Rows(Arc<SimResult>, Range<usize>),
}

/// The chunks not taken yet, every discrete state the run sent, and once it has ended, the
/// rows of its result not taken yet.
#[derive(Default)]
struct Queue {
    chunks: VecDeque<Chunk>,
    /// The run's rows sent so far: `0..sent`.
    sent: usize,
    discs: Vec<DiscreteState>,
    /// The ended run's result and its rows not taken yet (those not sent, up to the room).
    ended: Option<(Arc<SimResult>, Range<usize>)>,
    /// Pool jobs spawned to take work that have not left yet, and the most there may be.
    helpers: usize,
    most_helpers: usize,
    /// The run failed: nothing more is computed.
    failed: bool,
}

impl Queue {
    /// The next work: a chunk (the oldest, or the newest), else rows of the ended run.
    fn take(&mut self, newest: bool) -> Option<Work> {
        let chunk = match newest {
            true => self.chunks.pop_back(),
            false => self.chunks.pop_front(),
        };
        if let Some(chunk) = chunk {
            return Some(Work::Chunk(chunk));
        }
        let (result, rows) = self.ended.as_mut()?;
        if rows.start >= rows.end {
            return None;
        }
        let end = rows.end.min(rows.start + CHUNK);
        let taken = rows.start..end;
        rows.start = end;
        Some(Work::Rows(result.clone(), taken))
    }
}

/// The queue and what the threads share besides. A pool job never waits for work: it takes
/// what there is and leaves, and the run spawns another when it sends more (a job waiting for
/// rows would hold a pool thread for the whole run, and with it every other user of the pool).
#[derive(Default)]
struct Shared {
    queue: Mutex<Queue>,
    /// Chunks' rows already computed, whose memory the next chunks reuse (no allocation per
    /// chunk, and still in cache).
    spare: Mutex<Vec<Trajectory>>,
    /// Pool jobs computing right now (the calling thread waits for them awake at the end).
    busy: AtomicUsize,
}

impl Shared {
    fn lock(&self) -> MutexGuard<'_, Queue> {
        self.queue.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// A pool job's next work, the oldest chunk first; None when there is none now (the job
    /// then leaves). `discs` is brought up to every discrete state sent so far, under the lock
    /// the work is taken with.
    fn next(&self, discs: &mut Vec<DiscreteState>) -> Option<Work> {
        let mut queue = self.lock();
        let work = match queue.failed {
            true => None,
            false => queue.take(false),
        };
        match &work {
            Some(_) => discs.extend_from_slice(&queue.discs[discs.len()..]),
            None => queue.helpers -= 1,
        }
        work
    }

    /// How many pool jobs to spawn for the work now queued (each counted as a helper here).
    fn helpers_wanted(queue: &mut Queue) -> usize {
        let wanted = queue.most_helpers.saturating_sub(queue.helpers);
        queue.helpers += wanted;
        wanted
    }

    /// The run has ended: its rows `rows` (not sent) are to be computed too. Returns how many
    /// pool jobs to spawn for them.
    fn end(&self, result: Arc<SimResult>, rows: Range<usize>) -> usize {
        let mut queue = self.lock();
        queue.ended = Some((result, rows));
        Self::helpers_wanted(&mut queue)
    }

    /// The run failed: nothing more is computed.
    fn fail(&self) {
        self.lock().failed = true;
    }

    /// Memory for a chunk's rows: a computed chunk's, or new.
    fn rows_memory(&self) -> Trajectory {
        let mut spare = self.spare.lock().unwrap_or_else(PoisonError::into_inner);
        spare.pop().unwrap_or_default()
    }

    /// A computed chunk's rows, for the next chunk.
    fn give_back(&self, rows: Trajectory) {
        (self.spare.lock().unwrap_or_else(PoisonError::into_inner)).push(rows);
    }
}

/// A pool job at work: counted in `busy` while it lives; it fails the queue if it panics (the
/// run then sends nothing more: the scope lets the panic go on once the run returns).
struct AtWork<'a> {
    shared: &'a Shared,
    /// Dropped after `drop` below: the queue fails (if the job panics) once it has left `busy`.
    _failing: FailIfPanicking<'a>,
}

impl<'a> AtWork<'a> {
    fn start(shared: &'a Shared) -> Self {
        shared.busy.fetch_add(1, Ordering::AcqRel);
        let _failing = FailIfPanicking(shared);
        Self { shared, _failing }
    }
}

impl Drop for AtWork<'_> {
    fn drop(&mut self) {
        self.shared.busy.fetch_sub(1, Ordering::Release);
    }
}

/// Fails the queue when dropped while the thread panics: nothing more is computed.
struct FailIfPanicking<'a>(&'a Shared);

impl Drop for FailIfPanicking<'_> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            self.0.fail();
        }
    }
}

/// The table's cells, `width` per row, written by several threads at once, each its own rows.
struct Cells {
    first: *mut MaybeUninit<f64>,
    rows: usize,
    width: usize,
    stream: bool,
}

// SAFETY: `Cells` hands out the rows of a piece of work (`rows`) to the one thread that took it
// from the queue, and no two pieces share a row.
unsafe impl Send for Cells {}
unsafe impl Sync for Cells {}

impl Cells {
    /// The cells of rows `rows`.
    ///
    /// SAFETY: no other slice of these rows may be in use while this one is.
    #[allow(clippy::mut_from_ref)] // each row is handed to one thread alone (see `Send`)
    unsafe fn rows(&self, rows: Range<usize>) -> &mut [MaybeUninit<f64>] {
        assert!(
            rows.start <= rows.end && rows.end <= self.rows,
            "rows of the table"
        );
        let len = (rows.end - rows.start) * self.width;
        // SAFETY: in bounds (asserted), and not aliased (the caller's promise).
        unsafe { std::slice::from_raw_parts_mut(self.first.add(rows.start * self.width), len) }
    }
}

/// What the run hands its recorded rows to (`send`).
pub struct Feed<'a> {
    shared: &'a Shared,
    /// Rows the table has room for; rows beyond are computed once the run has ended.
    room: usize,
    /// Spawns a pool job that takes queued work; None: the rows are not sent (a pool of one
    /// thread, few rows, or a table beyond the memory guard).
    spawn: Option<&'a dyn Fn()>,
}

impl Feed<'_> {
    /// Hands the rows of `tr` (discrete states in `discs`) recorded since the last call to
    /// the pool's threads.
    pub fn send(&mut self, tr: &Trajectory, discs: &[DiscreteState]) {
        let Some(spawn) = self.spawn else {
            return;
        };
        // no more than `AHEAD` chunks waiting: the rows not sent are computed after the run
        // from the run's own trajectory, without a copy
        let (queued, sent) = {
            let queue = self.shared.lock();
            (queue.chunks.len(), queue.sent)
        };
        let most = sent + AHEAD.saturating_sub(queued) * CHUNK;
        let end = tr.rows().min(self.room).min(most);
        if end <= sent {
            return;
        }
        let chunks: Vec<Chunk> = (sent..end)
            .step_by(CHUNK)
            .map(|first| {
                let mut rows = self.shared.rows_memory();
                tr.copy_rows_into(first..(first + CHUNK).min(end), &mut rows);
                Chunk { first, rows }
            })
            .collect();
        let mut queue = self.shared.lock();
        let known = queue.discs.len();
        queue.discs.extend_from_slice(&discs[known..]);
        queue.chunks.extend(chunks);
        queue.sent = end;
        let wanted = Shared::helpers_wanted(&mut queue);
        drop(queue);
        (0..wanted).for_each(|_| spawn());
    }
}

/// Runs `run`, which hands its recorded rows to the `Feed` as it goes, while the pool's other
/// threads compute every variable of them; returns the run's result with its table computed
/// (about `rows` rows expected: more are computed once the run has ended). A table of more
/// than `limit` values is not computed: the result then refuses it when asked, as any result
/// that large does (`SimResult::check_table`).
pub fn recorded_while<E>(
    sys: &System,
    (rows, limit): (usize, f64),
    run: impl FnOnce(&mut Feed) -> Result<SimResult, E>,
) -> Result<SimResult, E> {
    let width = sys.outputs.len() + 1;
    let room = rows + rows / 8 + CHUNK;
    let shared = Shared::default();
    let mut feed = Feed {
        shared: &shared,
        room,
        spawn: None,
    };
    if (room * width) as f64 > limit {
        return run(&mut feed);
    }
    let own;
    let shape = match kept_shape(sys) {
        Some(shape) => shape,
        None => {
            own = Shape::new(sys, None);
            &own
        }
    };
    let mut data = table_memory(room * width);
    let cells = Cells {
        first: data.spare_capacity_mut().as_mut_ptr(),
        rows: room,
        width,
        stream: streams(room * width),
    };
    // the calling thread runs; the pool's other threads compute (one of them the caller's
    // own, when it is one of the pool)
    let helpers = match rows >= LIVE_FROM {
        true => rayon::current_num_threads().saturating_sub(1),
        false => 0,
    };
    let outcome = match helpers {
        // the table after the run, on every thread (`fill_rows` below)
        0 => run(&mut feed).map(|result| (result, 0)),
        _ => live(&shared, helpers, (&cells, sys, shape), room, run),
    };
    let (result, done) = match outcome {
        Ok(outcome) => outcome,
        Err(e) => {
            recycle_table(data);
            return Err(e);
        }
    };
    let total = result.rows() * width;
    // a run whose parameters changed has its table computed per system when asked; a table
    // of more values than fit in memory at once (the room did) is refused when asked
    if !result.earlier.is_empty() || total as f64 > limit {
        recycle_table(data);
        return Ok(result);
    }
    // SAFETY: rows 0..done were written: every chunk sent and every piece of the result's
    // rows in full (`fill_stretch` asserts it).
    unsafe { data.set_len(done * width) };
    if done < result.rows() {
        // the rows beyond the room, or all of them when no pool thread helps (on every thread)
        data.reserve_exact(total - data.len());
        let rest = &mut data.spare_capacity_mut()[..total - done * width];
        result.fill_rows(done..result.rows(), None, rest, |n| {
            stretch_rows(n, FEWEST_ROWS)
        });
        // SAFETY: `fill_rows` wrote every cell of the rows after `done`.
        unsafe { data.set_len(total) };
    }
    Ok(result.with_table(data))
}

/// The run (`run`) on this thread while up to `helpers` pool jobs at a time compute the chunks
/// it sends; once it has ended, every thread computes rows of its result (up to the table's
/// `room`) until none is left. The result, and the rows computed from 0.
fn live<E>(
    shared: &Shared,
    helpers: usize,
    (cells, sys, shape): (&Cells, &System, &Shape),
    room: usize,
    run: impl FnOnce(&mut Feed) -> Result<SimResult, E>,
) -> Result<(SimResult, usize), E> {
    shared.lock().most_helpers = helpers;
    let outcome = rayon::in_place_scope(|scope| {
        let spawn = || {
            scope.spawn(|_| {
                let _at_work = AtWork::start(shared);
                compute_queued(shared, cells, sys, shape);
            })
        };
        let mut feed = Feed {
            shared,
            room,
            spawn: Some(&spawn),
        };
        let _unwinding = FailIfPanicking(shared);
        let result = match run(&mut feed) {
            Ok(result) => Arc::new(result),
            Err(e) => {
                shared.fail();
                return Err(e);
            }
        };
        let sent = shared.lock().sent;
        // rows are only ever added to a run: every row sent is the result's
        let done = result.rows().min(room);
        if sent > done {
            shared.fail();
            return Ok((result, 0));
        }
        (0..shared.end(result.clone(), sent..done)).for_each(|_| spawn());
        // this thread takes the newest chunks, then rows of the result like the others
        let mut own = None;
        loop {
            // the lock only while taking (a `while let` would hold it through the body)
            let Some(work) = shared.lock().take(true) else {
                break;
            };
            let context = own.get_or_insert_with(|| (Block::new(shape), RowEvaluator::new(sys)));
            compute(&work, &result.discs, cells, sys, context);
        }
        drop(own);
        let start = Instant::now();
        while shared.busy.load(Ordering::Acquire) > 0 && start.elapsed() < WAIT_AWAKE {
            std::hint::spin_loop();
        }
        Ok((result, done))
        // leaving the scope waits (asleep) for pool jobs still computing, or not started
    });
    let (result, done) = outcome?;
    shared.lock().ended = None;
    // every other holder was a pool job's work, done by the end of the scope
    let result = Arc::into_inner(result).expect("the result held by this thread alone");
    Ok((result, done))
}

/// Rows the pool's threads computed while runs went on (for tests: that they did).
#[cfg(test)]
pub static ROWS_BY_POOL: AtomicUsize = AtomicUsize::new(0);

/// A pool job: the oldest chunks the run has sent, one after the other, then rows of its
/// result once it has ended, until there is none.
fn compute_queued(shared: &Shared, cells: &Cells, sys: &System, shape: &Shape) {
    let mut discs = Vec::new();
    let mut context = None;
    while let Some(work) = shared.next(&mut discs) {
        let context = context.get_or_insert_with(|| (Block::new(shape), RowEvaluator::new(sys)));
        compute(&work, &discs, cells, sys, context);
        if let Work::Chunk(chunk) = work {
            #[cfg(test)]
            ROWS_BY_POOL.fetch_add(chunk.rows.rows(), Ordering::Relaxed);
            shared.give_back(chunk.rows);
        }
        // a job that waits in the pool (another run's, another table's) runs in between: this
        // job may go on for the whole run
        rayon::yield_now();
    }
}

/// Computes and writes the rows of `work` (a chunk's discrete states in `discs`).
fn compute(
    work: &Work,
    discs: &[DiscreteState],
    cells: &Cells,
    sys: &System,
    context: &mut Context,
) {
    let (trajectory, rows, first) = match work {
        Work::Chunk(chunk) => {
            let rows = chunk.first..chunk.first + chunk.rows.rows();
            ((&chunk.rows, discs), rows, 0)
        }
        Work::Rows(result, rows) => {
            let trajectory = (&result.trajectory, &result.discs[..]);
            (trajectory, rows.clone(), rows.start)
        }
    };
    // SAFETY: a piece of work is taken from the queue by one thread alone, and its rows are in
    // no other.
    let data = unsafe { cells.rows(rows) };
    let mut out = Stretch::new(data, first, cells.width, cells.stream);
    fill_stretch(trajectory, sys, context, &mut out);
}
