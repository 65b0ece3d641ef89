//! Events: the zero-crossing indicators of the frozen relations (spec §10.1), and the event
//! iteration that drives the friction Booleans to MSL's fixed point (spec §1.6–1.7, §10.2).

mod crossings;
mod iteration;
pub mod relation;

pub use crossings::{indicator_count, indicator_label, indicators, speed_rates};
pub use iteration::{iterate, ModeCache, ModeChange};
