//! stiction's FMU runtime: FMI 2.0 Co-Simulation over `stiction_core::Simulation`, as a C-ABI
//! shared library (`libstiction_fmi.so`) that `stiction fmu` copies into an FMU's `binaries/`.
//! The model and its variable table come from the FMU's `resources/` at instantiation.

pub mod fmi2;
pub mod fmi3;
pub mod host;
pub mod instance;
pub mod layout;
pub mod serial;
pub mod snapshot;
pub mod types;
pub mod values;
