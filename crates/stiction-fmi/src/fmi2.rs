//! The FMI 2.0 Co-Simulation C API over `Instance`. Every entry point runs inside
//! `catch_unwind`: an error or a panic is logged through the host's logger and returned as
//! `fmi2Error`, never unwound into the host. Calls this runtime does not support (Model
//! Exchange, directional derivatives, input derivatives, asynchronous
//! steps) exist, since importers bind every symbol, and return `fmi2Error` with a message.
//!
//! Not merged (the duplicate finder pairs the entry points with each other and with
//! fmi3.rs's): each exported symbol is written out rather than made by a macro, so every FMI
//! name can be found as written; each is a line or two over `host::with` and `Instance`, where
//! the logic is written once.
#![allow(non_snake_case, clippy::missing_safety_doc)] // FMI's names; FMI 2.0 is the contract

use std::ffi::{c_int, CStr, CString};
use std::ptr;

use crate::host::{self, slice, slice_mut, text, with, Log, Slave};
use crate::instance::Instance;
use crate::types::*;

static TYPES_PLATFORM: &CStr = c"default";
static VERSION: &CStr = c"2.0";

#[no_mangle]
pub extern "C" fn fmi2GetTypesPlatform() -> FmiString {
    TYPES_PLATFORM.as_ptr()
}

#[no_mangle]
pub extern "C" fn fmi2GetVersion() -> FmiString {
    VERSION.as_ptr()
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: Component,
    on: Boolean,
    _n: usize,
    _categories: *const FmiString,
) -> Status {
    match (c as *mut Slave).as_mut() {
        Some(slave) => {
            slave.logging = on == FMI_TRUE;
            Status::Ok
        }
        None => Status::Error,
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Instantiate(
    name: FmiString,
    kind: c_int,
    guid: FmiString,
    resources: FmiString,
    functions: *const CallbackFunctions,
    _visible: Boolean,
    logging_on: Boolean,
) -> Component {
    let Some(callbacks) = functions.as_ref().copied() else {
        return ptr::null_mut();
    };
    let cname = CString::new(text(name)).unwrap_or_default();
    let (guid, resources) = (text(guid), text(resources));
    let log = Log::Fmi2(callbacks);
    host::instantiate(cname, log, logging_on == FMI_TRUE, || match kind {
        CO_SIMULATION => Instance::load(&resources, &guid),
        _ => Err("this FMU supports Co-Simulation only".to_string()),
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: Component) {
    host::free(c)
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: Component,
    tolerance_defined: Boolean,
    tolerance: Real,
    start: Real,
    stop_defined: Boolean,
    stop: Real,
) -> Status {
    let tol = (tolerance_defined == FMI_TRUE).then_some(tolerance);
    let stop = (stop_defined == FMI_TRUE).then_some(stop);
    with(c, "fmi2SetupExperiment", |i| {
        i.setup_experiment(tol, start, stop)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: Component) -> Status {
    with(c, "fmi2EnterInitializationMode", |i| {
        i.enter_initialization()
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: Component) -> Status {
    with(c, "fmi2ExitInitializationMode", |i| i.exit_initialization())
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Terminate(c: Component) -> Status {
    with(c, "fmi2Terminate", |i| i.terminate())
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Reset(c: Component) -> Status {
    with(c, "fmi2Reset", |i| {
        i.reset();
        Ok(())
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetReal(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    value: *mut Real,
) -> Status {
    with(c, "fmi2GetReal", |i| {
        i.get_values(slice(vr, n), false, slice_mut(value, n))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetReal(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    value: *const Real,
) -> Status {
    with(c, "fmi2SetReal", |i| {
        i.set_values(slice(vr, n), false, slice(value, n))
    })
}

/// The calls for types this FMU has no variables of: any value reference is unknown.
unsafe fn no_variables(c: Component, call: &str, n: usize) -> Status {
    with(c, call, |_| match n {
        0 => Ok(()),
        _ => Err("this FMU has no variables of this type".into()),
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetInteger(
    c: Component,
    _vr: *const ValueReference,
    n: usize,
    _v: *mut Integer,
) -> Status {
    no_variables(c, "fmi2GetInteger", n)
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetInteger(
    c: Component,
    _vr: *const ValueReference,
    n: usize,
    _v: *const Integer,
) -> Status {
    no_variables(c, "fmi2SetInteger", n)
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetBoolean(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    value: *mut Boolean,
) -> Status {
    with(c, "fmi2GetBoolean", |i| {
        let mut values = vec![0.0; n];
        i.get_values(slice(vr, n), true, &mut values)?;
        for (out, v) in slice_mut(value, n).iter_mut().zip(values) {
            *out = Boolean::from(v != 0.0);
        }
        Ok(())
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    value: *const Boolean,
) -> Status {
    with(c, "fmi2SetBoolean", |i| {
        let values: Vec<f64> = slice(value, n)
            .iter()
            .map(|&b| (b != 0) as u8 as f64)
            .collect();
        i.set_values(slice(vr, n), true, &values)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetString(
    c: Component,
    _vr: *const ValueReference,
    n: usize,
    _v: *mut FmiString,
) -> Status {
    no_variables(c, "fmi2GetString", n)
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetString(
    c: Component,
    _vr: *const ValueReference,
    n: usize,
    _v: *const FmiString,
) -> Status {
    no_variables(c, "fmi2SetString", n)
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(c: Component, state: *mut FmuState) -> Status {
    with(c, "fmi2GetFMUstate", |i| host::get_state(i, state))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: Component, state: FmuState) -> Status {
    with(c, "fmi2SetFMUstate", |i| host::set_state(i, state))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(c: Component, state: *mut FmuState) -> Status {
    with(c, "fmi2FreeFMUstate", |_| host::free_state(state))
}

unsafe fn unsupported(c: Component, call: &str) -> Status {
    with(c, call, |_| {
        Err("not supported by this FMU (see its capability flags)".into())
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: Component,
    s: FmuState,
    n: *mut usize,
) -> Status {
    with(c, "fmi2SerializedFMUstateSize", |i| {
        host::serialized_size(i, s, n)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: Component,
    s: FmuState,
    b: *mut Byte,
    n: usize,
) -> Status {
    with(c, "fmi2SerializeFMUstate", |i| {
        host::serialize(i, s, b as *mut u8, n)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: Component,
    b: *const Byte,
    n: usize,
    s: *mut FmuState,
) -> Status {
    with(c, "fmi2DeSerializeFMUstate", |i| {
        host::deserialize(i, b as *const u8, n, s)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: Component,
    _unknown: *const ValueReference,
    _nu: usize,
    _known: *const ValueReference,
    _nk: usize,
    _dv_known: *const Real,
    _dv_unknown: *mut Real,
) -> Status {
    unsupported(c, "fmi2GetDirectionalDerivative")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: Component,
    _vr: *const ValueReference,
    _n: usize,
    _order: *const Integer,
    _v: *const Real,
) -> Status {
    unsupported(c, "fmi2SetRealInputDerivatives")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: Component,
    _vr: *const ValueReference,
    _n: usize,
    _order: *const Integer,
    _v: *mut Real,
) -> Status {
    unsupported(c, "fmi2GetRealOutputDerivatives")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2DoStep(c: Component, t: Real, h: Real, _no_prior: Boolean) -> Status {
    with(c, "fmi2DoStep", |i| i.do_step(t, h))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2CancelStep(c: Component) -> Status {
    unsupported(c, "fmi2CancelStep")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetStatus(c: Component, _kind: c_int, _v: *mut Status) -> Status {
    unsupported(c, "fmi2GetStatus")
}

/// `fmi2LastSuccessfulTime` (kind 2): the time the run reached.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealStatus(c: Component, kind: c_int, value: *mut Real) -> Status {
    with(c, "fmi2GetRealStatus", |i| {
        let out = value.as_mut().ok_or("value is a null pointer")?;
        match (kind, i.time()) {
            (2, Some(t)) => {
                *out = t;
                Ok(())
            }
            _ => Err(format!("status kind {kind} is not available")),
        }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: Component,
    _kind: c_int,
    _v: *mut Integer,
) -> Status {
    unsupported(c, "fmi2GetIntegerStatus")
}

/// `fmi2Terminated` (kind 3): never requested by this FMU.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: Component,
    kind: c_int,
    value: *mut Boolean,
) -> Status {
    with(c, "fmi2GetBooleanStatus", |_| {
        let out = value.as_mut().ok_or("value is a null pointer")?;
        match kind {
            3 => {
                *out = 0;
                Ok(())
            }
            _ => Err(format!("status kind {kind} is not available")),
        }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetStringStatus(
    c: Component,
    _kind: c_int,
    _v: *mut FmiString,
) -> Status {
    unsupported(c, "fmi2GetStringStatus")
}
