//! The FMI 2.0 Co-Simulation C API over `Instance`. Every entry point runs inside
//! `catch_unwind`: an error or a panic is logged through the host's logger and returned as
//! `fmi2Error`, never unwound into the host. Calls this runtime does not support (Model
//! Exchange, directional derivatives, input derivatives, serialized states, asynchronous
//! steps) exist, since importers bind every symbol, and return `fmi2Error` with a message.
#![allow(non_snake_case, clippy::missing_safety_doc)] // FMI's names; FMI 2.0 is the contract

use std::ffi::{c_int, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr;

use crate::instance::{Fallible, Instance, Snapshot};
use crate::types::*;

/// What `fmi2Component` points to: the instance, its name and the host's callbacks.
pub struct Slave {
    name: CString,
    callbacks: CallbackFunctions,
    logging: bool,
    pub inner: Instance,
}

impl Slave {
    fn log(&self, status: Status, category: &str, message: &str) {
        if status != Status::Ok || self.logging {
            emit(&self.callbacks, &self.name, status, category, message);
        }
    }
}

/// Hands a message to the host's logger, through `"%s"` (it is printf-style).
fn emit(callbacks: &CallbackFunctions, name: &CStr, status: Status, category: &str, message: &str) {
    let Some(logger) = callbacks.logger else {
        return;
    };
    let category = CString::new(category).unwrap_or_default();
    let message = CString::new(message.replace('\0', " ")).unwrap_or_default();
    let env = callbacks.component_environment;
    let (name, category, message) = (name.as_ptr(), category.as_ptr(), message.as_ptr());
    // SAFETY: the host's logger, called as FMI 2.0 defines it, with valid C strings
    unsafe { logger(env, name, status, category, c"%s".as_ptr(), message) }
}

fn panic_text(payload: Box<dyn std::any::Any + Send>) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into())
}

/// Runs `f` on the instance `c` points to; errors and panics become a logged `fmi2Error`.
unsafe fn with(c: Component, call: &str, f: impl FnOnce(&mut Instance) -> Fallible<()>) -> Status {
    let Some(slave) = (c as *mut Slave).as_mut() else {
        return Status::Error;
    };
    let outcome = catch_unwind(AssertUnwindSafe(|| f(&mut slave.inner)));
    let message = match outcome {
        Ok(Ok(())) => return Status::Ok,
        Ok(Err(message)) => message,
        Err(payload) => format!("internal error (please report): {}", panic_text(payload)),
    };
    slave.log(
        Status::Error,
        "logStatusError",
        &format!("{call}: {message}"),
    );
    Status::Error
}

unsafe fn text(s: FmiString) -> String {
    if s.is_null() {
        return String::new();
    }
    CStr::from_ptr(s).to_string_lossy().into_owned()
}

unsafe fn slice<'a, T>(p: *const T, n: usize) -> &'a [T] {
    if n == 0 || p.is_null() {
        return &[];
    }
    std::slice::from_raw_parts(p, n)
}

unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> &'a mut [T] {
    if n == 0 || p.is_null() {
        return &mut [];
    }
    std::slice::from_raw_parts_mut(p, n)
}

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

fn fail_instantiate(callbacks: &CallbackFunctions, name: &CStr, message: &str) -> Component {
    let message = format!("fmi2Instantiate: {message}");
    emit(callbacks, name, Status::Error, "logStatusError", &message);
    ptr::null_mut()
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
    let loaded = catch_unwind(|| match kind {
        CO_SIMULATION => Instance::load(&resources, &guid),
        _ => Err("this FMU supports Co-Simulation only".to_string()),
    });
    let instance = match loaded {
        Ok(Ok(instance)) => instance,
        Ok(Err(message)) => return fail_instantiate(&callbacks, &cname, &message),
        Err(payload) => return fail_instantiate(&callbacks, &cname, &panic_text(payload)),
    };
    let slave = Box::new(Slave {
        name: cname,
        callbacks,
        logging: logging_on == FMI_TRUE,
        inner: instance,
    });
    Box::into_raw(slave) as Component
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: Component) {
    if !c.is_null() {
        let _ = catch_unwind(|| drop(Box::from_raw(c as *mut Slave)));
    }
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
        i.get_reals(slice(vr, n), slice_mut(value, n))
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
        i.set_reals(slice(vr, n), slice(value, n))
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
    _vr: *const ValueReference,
    n: usize,
    _v: *mut Boolean,
) -> Status {
    no_variables(c, "fmi2GetBoolean", n)
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: Component,
    _vr: *const ValueReference,
    n: usize,
    _v: *const Boolean,
) -> Status {
    no_variables(c, "fmi2SetBoolean", n)
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
    with(c, "fmi2GetFMUstate", |i| {
        let out = state.as_mut().ok_or("FMUstate is a null pointer")?;
        let snap = i.snapshot()?;
        match (*out as *mut Snapshot).as_mut() {
            Some(old) => *old = snap,
            None => *out = Box::into_raw(Box::new(snap)) as FmuState,
        }
        Ok(())
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: Component, state: FmuState) -> Status {
    with(c, "fmi2SetFMUstate", |i| {
        let snap = (state as *const Snapshot)
            .as_ref()
            .ok_or("FMUstate is a null pointer")?;
        i.restore(snap)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(c: Component, state: *mut FmuState) -> Status {
    with(c, "fmi2FreeFMUstate", |_| {
        if let Some(p) = state.as_mut() {
            if !p.is_null() {
                drop(Box::from_raw(*p as *mut Snapshot));
            }
            *p = ptr::null_mut();
        }
        Ok(())
    })
}

unsafe fn unsupported(c: Component, call: &str) -> Status {
    with(c, call, |_| {
        Err("not supported by this FMU (see its capability flags)".into())
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: Component,
    _s: FmuState,
    _n: *mut usize,
) -> Status {
    unsupported(c, "fmi2SerializedFMUstateSize")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: Component,
    _s: FmuState,
    _b: *mut Byte,
    _n: usize,
) -> Status {
    unsupported(c, "fmi2SerializeFMUstate")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: Component,
    _b: *const Byte,
    _n: usize,
    _s: *mut FmuState,
) -> Status {
    unsupported(c, "fmi2DeSerializeFMUstate")
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
