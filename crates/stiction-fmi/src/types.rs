//! The FMI 2.0 C types this runtime needs, written out by hand from `fmi2TypesPlatform.h` and
//! `fmi2FunctionTypes.h` (FMI 2.0.4). They are a handful of plain aliases and one struct; the
//! crates that carry them (`fmi-sys`) generate the whole API with bindgen at build time, a
//! dependency (libclang) out of proportion to these lines.

use std::ffi::{c_char, c_int, c_uint, c_void};

pub type Component = *mut c_void;
pub type ComponentEnvironment = *mut c_void;
pub type FmuState = *mut c_void;
pub type ValueReference = c_uint;
pub type Real = f64;
pub type Integer = c_int;
pub type Boolean = c_int;
pub type FmiString = *const c_char;
pub type Byte = c_char;

pub const FMI_TRUE: Boolean = 1;

/// `fmi2Status`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    Ok = 0,
    Warning = 1,
    Discard = 2,
    Error = 3,
    Fatal = 4,
    Pending = 5,
}

/// `fmi2Type`: this runtime is Co-Simulation only.
pub const CO_SIMULATION: c_int = 1;

/// `fmi2CallbackLogger`: printf-style, so the message is always passed through `"%s"`.
pub type Logger = Option<
    unsafe extern "C" fn(ComponentEnvironment, FmiString, Status, FmiString, FmiString, ...),
>;

/// `fmi2CallbackFunctions`.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct CallbackFunctions {
    pub logger: Logger,
    pub allocate_memory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    pub free_memory: Option<unsafe extern "C" fn(*mut c_void)>,
    pub step_finished: Option<unsafe extern "C" fn(ComponentEnvironment, Status)>,
    pub component_environment: ComponentEnvironment,
}
