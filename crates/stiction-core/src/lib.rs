//! stiction-core: rotational drivetrains with exact Coulomb friction, as the Modelica Standard
//! Library defines it (state events, no smoothing). Pure Rust; the Python bindings are elsewhere.
//!
//! This file is the crate's one API surface: the modules are private, and everything the
//! bindings (stiction-py, stiction-fmi), the examples and the integration tests may use is
//! re-exported here, so outside code writes `stiction_core::Name` and never a module path. A
//! name added here is a promise to those crates; anything else may move freely inside.
//!
//! The modules in their layer order, from the bottom (each imports only modules before it;
//! `scripts/check_structure.py` checks the order, docs/architecture.md explains it).

// the error types
mod error;
// linear solvers (dense, banded, refactoring) and the rank test
mod linalg;
// the model description: ModelSpec, Params, declarations
mod model;
// interpolation tables (CombiTable1D)
mod lookup_table;
// node coordinates: rows over node angles
mod rel;
// stick/slip and quadrant logic: the SwitchingElement trait and its implementations
mod switching;
// the run-time signal network
mod signals;
// the run-time thermal network
mod thermal;
// pad wear of friction elements at run time
mod wear;
// the assembled System and the Builder components contribute through
mod system;
// the component constructors
mod components;
// creating components, resolving the topology, building; CompiledModel
mod assembly;
// every component type's parameters, ports and variables
mod catalogue;
// evaluation, per-mode solve, crossings, event iteration
mod engine;
// the recorded run, its variables, metrics and files
mod result;
// the MSL tube comparison of a result against a reference
mod compare;
// the resumable run
mod simulation;
// the start-value report
mod start_report;
// variants of a compiled model on threads
mod sweep;

// ---- the model and its errors
pub use error::{ModelError, ModelResult, SimError};
pub use model::{Experiment, ModelSpec, ParamKind};

// ---- building: components, the assembled system, compiled models, the catalogue
pub use assembly::{assemble, CompiledModel, Recompiled};
pub use catalogue::{catalogue, TypeInfo};
pub use components::create as create_component;
pub use system::System;

// ---- running
pub use signals::same_instant;
pub use simulation::{
    check_model, initial_state, run, run_recording_all, simulate, CancelHandle, Cursor,
    InputChange, ParameterChange, SimState, Simulation,
};
// the bytes of a saved run (the FMU's serialized states and Python's pickles write them)
pub use simulation::{ByteReader, ByteWriter, ReadResult, STATE_BYTES_VERSION};
pub use start_report::{report as initialization_report, StartValue, Status as StartStatus};
pub use sweep::{run_variants, Outcome, Override, Plan};

// ---- results and their files
pub use result::io::{write_csv, write_mat, Parameter as MatParameter};
pub use result::{recycle_table, ElementAudit, EventRecord, SimResult};

// ---- the MSL tube comparison (the regression oracle of the tests and of `stiction compare`)
pub use compare::{
    check_signal, compare, read_signal_list, tube, Columns, CompareError, Reference, Side,
    SignalCheck, SignalReport, Tube, FLOOR as TUBE_FLOOR,
};

// ---- the engine's parts the integration tests check on their own (the banded refactorization
// against dense LU)
pub use engine::kkt::ModeMatrix;
pub use engine::ModeSolver;
pub use linalg::DenseLu;
pub use switching::element::ModeKey;
