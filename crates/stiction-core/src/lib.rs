//! stiction-core: rotational drivetrains with exact Coulomb friction, as the Modelica Standard
//! Library defines it (state events, no smoothing). Pure Rust; the Python bindings are elsewhere.

pub mod assembly;
pub mod catalogue;
pub mod compare;
pub mod components;
pub mod engine;
pub mod error;
pub mod initialization;
pub mod linalg;
pub mod model;
pub mod rel;
pub mod result;
pub mod signals;
pub mod simulation;
pub mod sweep;
pub mod switching;
pub mod system;
pub mod table;
pub mod thermal;

pub use error::{ModelError, SimError};
pub use model::ModelSpec;
pub use result::SimResult;
pub use simulation::{simulate, Simulation};
