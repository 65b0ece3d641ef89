//! The engine: one evaluation of the assembled system in a discrete state (`eval`), the
//! per-mode linear solve (`kkt`, over the interfaces of `linalg`), the zero-crossing indicators of the frozen relations
//! (`crossings`, spec §10.1) and the event iteration that drives the switching elements to
//! MSL's fixed point (`iteration`, spec §1.6–1.7, §10.2).

mod crossings;
pub mod eval;
mod iteration;
pub mod kkt;
pub mod massless;
mod mode_solver;

pub use crossings::{indicator_count, indicator_label, indicators, speed_rates, wear_indicator};
pub use iteration::{iterate, EventPoint, ModeCache};
pub use mode_solver::ModeSolver;
