//! The FMI 3.0 Co-Simulation C API over the same `Instance` as FMI 2.0. Steps run to their end,
//! or, if the host allows early return, to the first friction event in them (no event mode:
//! the events are handled inside the step either way). Every
//! function an importer binds exists; those for Model Exchange, Scheduled Execution, clocks,
//! derivatives and the integer, string and binary types return
//! `fmi3Error` with a logged message.
//!
//! Not merged (the duplicate finder pairs the entry points with each other and with
//! fmi2.rs's): each exported symbol is written out rather than made by a macro, so every FMI
//! name can be found as written; each is a line or two over `host::with` and `Instance`, where
//! the logic is written once.
#![allow(non_snake_case, clippy::missing_safety_doc)] // FMI's names; FMI 3.0 is the contract

use std::ffi::{c_char, c_void, CStr, CString};

use crate::host::{self, slice, slice_mut, text, with, Log, LogMessage3, Slave};
use crate::instance::Instance;
use crate::types::Status;

type Inst = *mut c_void;
type Vr = *const u32;

static VERSION: &CStr = c"3.0";

#[no_mangle]
pub extern "C" fn fmi3GetVersion() -> *const c_char {
    VERSION.as_ptr()
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetDebugLogging(
    c: Inst,
    on: bool,
    _n: usize,
    _categories: *const *const c_char,
) -> Status {
    match (c as *mut Slave).as_mut() {
        Some(slave) => {
            slave.logging = on;
            Status::Ok
        }
        None => Status::Error,
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
    name: *const c_char,
    token: *const c_char,
    resources: *const c_char,
    _visible: bool,
    logging_on: bool,
    _event_mode_used: bool,
    early_return_allowed: bool,
    _required_intermediate: Vr,
    _n_required: usize,
    env: *mut c_void,
    logger: LogMessage3,
    _intermediate_update: *mut c_void,
) -> Inst {
    let cname = CString::new(text(name)).unwrap_or_default();
    let (token, resources) = (text(token), text(resources));
    let log = Log::Fmi3 { env, logger };
    host::instantiate(cname, log, logging_on, || {
        let mut instance = Instance::load(&resources, &token)?;
        instance.early_return = early_return_allowed;
        Ok(instance)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3FreeInstance(c: Inst) {
    host::free(c)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EnterInitializationMode(
    c: Inst,
    tolerance_defined: bool,
    tolerance: f64,
    start: f64,
    stop_defined: bool,
    stop: f64,
) -> Status {
    let tol = tolerance_defined.then_some(tolerance);
    let stop = stop_defined.then_some(stop);
    with(c, "fmi3EnterInitializationMode", |i| {
        i.setup_experiment(tol, start, stop)?;
        i.enter_initialization()
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3ExitInitializationMode(c: Inst) -> Status {
    with(c, "fmi3ExitInitializationMode", |i| i.exit_initialization())
}

#[no_mangle]
pub unsafe extern "C" fn fmi3Terminate(c: Inst) -> Status {
    with(c, "fmi3Terminate", |i| i.terminate())
}

#[no_mangle]
pub unsafe extern "C" fn fmi3Reset(c: Inst) -> Status {
    with(c, "fmi3Reset", |i| {
        i.reset();
        Ok(())
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetFloat64(
    c: Inst,
    vr: Vr,
    nvr: usize,
    v: *mut f64,
    n: usize,
) -> Status {
    with(c, "fmi3GetFloat64", |i| {
        i.get_values(slice(vr, nvr), false, slice_mut(v, n))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetFloat64(
    c: Inst,
    vr: Vr,
    nvr: usize,
    v: *const f64,
    n: usize,
) -> Status {
    with(c, "fmi3SetFloat64", |i| {
        i.set_values(slice(vr, nvr), false, slice(v, n))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetBoolean(
    c: Inst,
    vr: Vr,
    nvr: usize,
    v: *mut bool,
    n: usize,
) -> Status {
    with(c, "fmi3GetBoolean", |i| {
        let mut values = vec![0.0; n];
        i.get_values(slice(vr, nvr), true, &mut values)?;
        for (out, x) in slice_mut(v, n).iter_mut().zip(values) {
            *out = x != 0.0;
        }
        Ok(())
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetBoolean(
    c: Inst,
    vr: Vr,
    nvr: usize,
    v: *const bool,
    n: usize,
) -> Status {
    with(c, "fmi3SetBoolean", |i| {
        // read as bytes: a host's `bool` other than 0 or 1 is true, not undefined behaviour
        let bytes = slice(v as *const u8, n);
        let values: Vec<f64> = bytes.iter().map(|&b| (b != 0) as u8 as f64).collect();
        i.set_values(slice(vr, nvr), true, &values)
    })
}

/// Runs the step to its end: no event needs the host, no early return.
#[no_mangle]
pub unsafe extern "C" fn fmi3DoStep(
    c: Inst,
    t: f64,
    h: f64,
    _no_prior: bool,
    event_handling_needed: *mut bool,
    terminate: *mut bool,
    early_return: *mut bool,
    last_successful_time: *mut f64,
) -> Status {
    with(c, "fmi3DoStep", |i| {
        let outcome = i.do_step(t, h);
        for flag in [event_handling_needed, terminate, early_return] {
            if let Some(flag) = flag.as_mut() {
                *flag = false;
            }
        }
        if let (Some(out), Some(now)) = (last_successful_time.as_mut(), i.time()) {
            *out = now;
            // stopped at a friction event before the step's end (only if the host allows it)
            if let Some(early) = early_return.as_mut() {
                *early = i.returned_early;
            }
        }
        outcome
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetFMUState(c: Inst, state: *mut *mut c_void) -> Status {
    with(c, "fmi3GetFMUState", |i| host::get_state(i, state))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetFMUState(c: Inst, state: *mut c_void) -> Status {
    with(c, "fmi3SetFMUState", |i| host::set_state(i, state))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3FreeFMUState(c: Inst, state: *mut *mut c_void) -> Status {
    with(c, "fmi3FreeFMUState", |_| host::free_state(state))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
    c: Inst,
    s: *mut c_void,
    n: *mut usize,
) -> Status {
    with(c, "fmi3SerializedFMUStateSize", |i| {
        host::serialized_size(i, s, n)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SerializeFMUState(
    c: Inst,
    s: *mut c_void,
    b: *mut u8,
    n: usize,
) -> Status {
    with(c, "fmi3SerializeFMUState", |i| host::serialize(i, s, b, n))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3DeserializeFMUState(
    c: Inst,
    b: *const u8,
    n: usize,
    s: *mut *mut c_void,
) -> Status {
    with(c, "fmi3DeserializeFMUState", |i| {
        host::deserialize(i, b, n, s)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateModelExchange(
    _name: *const c_char,
    _token: *const c_char,
    _resources: *const c_char,
    _visible: bool,
    _logging_on: bool,
    _env: *mut c_void,
    _logger: LogMessage3,
) -> Inst {
    std::ptr::null_mut()
}

#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateScheduledExecution(
    _name: *const c_char,
    _token: *const c_char,
    _resources: *const c_char,
    _visible: bool,
    _logging_on: bool,
    _env: *mut c_void,
    _logger: LogMessage3,
    _clock_update: *mut c_void,
    _lock: *mut c_void,
    _unlock: *mut c_void,
) -> Inst {
    std::ptr::null_mut()
}

/// The entry points this FMU does not support, each with its exact C signature (after the
/// instance): they log and return `fmi3Error`.
macro_rules! unsupported {
    ($($name:ident($($t:ty),*);)*) => {$(
        #[no_mangle]
        pub unsafe extern "C" fn $name(c: Inst, $(_: $t),*) -> Status {
            with(c, stringify!($name), |_| Err("not supported by this FMU".into()))
        }
    )*};
}

type Out<T> = *mut T;
type In<T> = *const T;

unsupported! {
    fmi3EnterEventMode();
    fmi3EnterStepMode();
    fmi3EnterConfigurationMode();
    fmi3ExitConfigurationMode();
    fmi3EnterContinuousTimeMode();
    fmi3EvaluateDiscreteStates();
    fmi3UpdateDiscreteStates(Out<bool>, Out<bool>, Out<bool>, Out<bool>, Out<bool>, Out<f64>);
    fmi3CompletedIntegratorStep(bool, Out<bool>, Out<bool>);
    fmi3SetTime(f64);
    fmi3SetContinuousStates(In<f64>, usize);
    fmi3GetContinuousStates(Out<f64>, usize);
    fmi3GetContinuousStateDerivatives(Out<f64>, usize);
    fmi3GetNominalsOfContinuousStates(Out<f64>, usize);
    fmi3GetEventIndicators(Out<f64>, usize);
    fmi3GetNumberOfContinuousStates(Out<usize>);
    fmi3GetNumberOfEventIndicators(Out<usize>);
    fmi3GetNumberOfVariableDependencies(u32, Out<usize>);
    fmi3GetVariableDependencies(u32, Out<usize>, Out<u32>, Out<usize>, Out<i32>, usize);
    fmi3GetDirectionalDerivative(Vr, usize, Vr, usize, In<f64>, usize, Out<f64>, usize);
    fmi3GetAdjointDerivative(Vr, usize, Vr, usize, In<f64>, usize, Out<f64>, usize);
    fmi3GetOutputDerivatives(Vr, usize, In<i32>, Out<f64>, usize);
    fmi3ActivateModelPartition(u32, f64);
    fmi3GetFloat32(Vr, usize, Out<f32>, usize);
    fmi3SetFloat32(Vr, usize, In<f32>, usize);
    fmi3GetInt8(Vr, usize, Out<i8>, usize);
    fmi3SetInt8(Vr, usize, In<i8>, usize);
    fmi3GetUInt8(Vr, usize, Out<u8>, usize);
    fmi3SetUInt8(Vr, usize, In<u8>, usize);
    fmi3GetInt16(Vr, usize, Out<i16>, usize);
    fmi3SetInt16(Vr, usize, In<i16>, usize);
    fmi3GetUInt16(Vr, usize, Out<u16>, usize);
    fmi3SetUInt16(Vr, usize, In<u16>, usize);
    fmi3GetInt32(Vr, usize, Out<i32>, usize);
    fmi3SetInt32(Vr, usize, In<i32>, usize);
    fmi3GetUInt32(Vr, usize, Out<u32>, usize);
    fmi3SetUInt32(Vr, usize, In<u32>, usize);
    fmi3GetInt64(Vr, usize, Out<i64>, usize);
    fmi3SetInt64(Vr, usize, In<i64>, usize);
    fmi3GetUInt64(Vr, usize, Out<u64>, usize);
    fmi3SetUInt64(Vr, usize, In<u64>, usize);
    fmi3GetString(Vr, usize, Out<*const c_char>, usize);
    fmi3SetString(Vr, usize, In<*const c_char>, usize);
    fmi3GetBinary(Vr, usize, Out<usize>, Out<*const u8>, usize);
    fmi3SetBinary(Vr, usize, In<usize>, In<*const u8>, usize);
    fmi3GetClock(Vr, usize, Out<bool>);
    fmi3SetClock(Vr, usize, In<bool>);
    fmi3GetIntervalDecimal(Vr, usize, Out<f64>, Out<i32>);
    fmi3GetIntervalFraction(Vr, usize, Out<u64>, Out<u64>, Out<i32>);
    fmi3GetShiftDecimal(Vr, usize, Out<f64>);
    fmi3GetShiftFraction(Vr, usize, Out<u64>, Out<u64>);
    fmi3SetIntervalDecimal(Vr, usize, In<f64>);
    fmi3SetIntervalFraction(Vr, usize, In<u64>, In<u64>);
    fmi3SetShiftDecimal(Vr, usize, In<f64>);
    fmi3SetShiftFraction(Vr, usize, In<u64>, In<u64>);
}
