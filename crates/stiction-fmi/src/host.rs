//! What both C APIs share: the object an instance handle points to (the instance, its name and
//! the host's logger), the guard every entry point runs in (`catch_unwind`; an error or a panic
//! is logged and becomes an error status, never an unwind into the host), and the conversions
//! of C arguments.

use std::ffi::{c_void, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

use crate::instance::Instance;
use crate::serial;
use crate::snapshot::{Fallible, Snapshot};
use crate::types::{CallbackFunctions, FmiString, Status};

/// FMI 3.0's `fmi3LogMessageCallback` (not printf-style, no instance name).
pub type LogMessage3 = Option<unsafe extern "C" fn(*mut c_void, Status, FmiString, FmiString)>;

/// The host's logger, as each FMI version passes it.
pub enum Log {
    Fmi2(CallbackFunctions),
    Fmi3 {
        env: *mut c_void,
        logger: LogMessage3,
    },
}

/// What an `fmi2Component` / `fmi3Instance` points to.
pub struct Slave {
    pub name: CString,
    pub log: Log,
    pub logging: bool,
    pub inner: Instance,
}

impl Slave {
    pub fn log(&self, status: Status, category: &str, message: &str) {
        if status != Status::Ok || self.logging {
            emit(&self.log, &self.name, status, category, message);
        }
    }
}

/// Hands a message to the host's logger (FMI 2.0's is printf-style: always through `"%s"`).
pub fn emit(log: &Log, name: &CStr, status: Status, category: &str, message: &str) {
    let category = CString::new(category).unwrap_or_default();
    let message = CString::new(message.replace('\0', " ")).unwrap_or_default();
    let (category, message) = (category.as_ptr(), message.as_ptr());
    match log {
        // SAFETY: the host's loggers, called as the standard defines them, with C strings
        Log::Fmi2(cb) => {
            if let Some(logger) = cb.logger {
                let env = cb.component_environment;
                unsafe {
                    logger(
                        env,
                        name.as_ptr(),
                        status,
                        category,
                        c"%s".as_ptr(),
                        message,
                    )
                }
            }
        }
        Log::Fmi3 { env, logger } => {
            if let Some(logger) = logger {
                unsafe { logger(*env, status, category, message) }
            }
        }
    }
}

pub fn panic_text(payload: Box<dyn std::any::Any + Send>) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into())
}

/// Runs `f` on the instance `c` points to; errors and panics become a logged error status.
///
/// # Safety
/// `c` is null or a handle this library returned and has not freed.
pub unsafe fn with(
    c: *mut c_void,
    call: &str,
    f: impl FnOnce(&mut Instance) -> Fallible<()>,
) -> Status {
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

/// Loads an instance; on failure logs through `log` and gives null.
pub fn instantiate(
    name: CString,
    log: Log,
    logging: bool,
    load: impl FnOnce() -> Fallible<Instance>,
) -> *mut c_void {
    let loaded = catch_unwind(AssertUnwindSafe(load));
    let message = match loaded {
        Ok(Ok(inner)) => {
            let slave = Slave {
                name,
                log,
                logging,
                inner,
            };
            return Box::into_raw(Box::new(slave)) as *mut c_void;
        }
        Ok(Err(message)) => message,
        Err(payload) => panic_text(payload),
    };
    emit(
        &log,
        &name,
        Status::Error,
        "logStatusError",
        &format!("instantiate: {message}"),
    );
    std::ptr::null_mut()
}

/// Frees an instance made by `instantiate`.
///
/// # Safety
/// `c` is null or a handle this library returned and has not freed.
pub unsafe fn free(c: *mut c_void) {
    if !c.is_null() {
        let _ = catch_unwind(|| drop(Box::from_raw(c as *mut Slave)));
    }
}

/// # Safety
/// `s` is null or a NUL-terminated string.
pub unsafe fn text(s: FmiString) -> String {
    if s.is_null() {
        return String::new();
    }
    CStr::from_ptr(s).to_string_lossy().into_owned()
}

/// # Safety
/// `p` is null or points to `n` values.
pub unsafe fn slice<'a, T>(p: *const T, n: usize) -> &'a [T] {
    if n == 0 || p.is_null() {
        return &[];
    }
    std::slice::from_raw_parts(p, n)
}

/// # Safety
/// `p` is null or points to `n` values the caller lets us write.
pub unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> &'a mut [T] {
    if n == 0 || p.is_null() {
        return &mut [];
    }
    std::slice::from_raw_parts_mut(p, n)
}

/// `getFMUstate`: a new saved state, or the one `*state` points to overwritten.
///
/// # Safety
/// `state` is null or points to null or to a state this library made.
pub unsafe fn get_state(i: &mut Instance, state: *mut *mut c_void) -> Fallible<()> {
    let out = state.as_mut().ok_or("FMUstate is a null pointer")?;
    let snap = i.snapshot()?;
    match (*out as *mut Snapshot).as_mut() {
        Some(old) => *old = snap,
        None => *out = Box::into_raw(Box::new(snap)) as *mut c_void,
    }
    Ok(())
}

/// # Safety
/// `state` is null or a state this library made.
pub unsafe fn set_state(i: &mut Instance, state: *mut c_void) -> Fallible<()> {
    let snap = (state as *const Snapshot)
        .as_ref()
        .ok_or("FMUstate is a null pointer")?;
    i.restore(snap)
}

/// # Safety
/// `state` is null or points to null or to a state this library made.
pub unsafe fn free_state(state: *mut *mut c_void) -> Fallible<()> {
    if let Some(p) = state.as_mut() {
        if !p.is_null() {
            drop(Box::from_raw(*p as *mut Snapshot));
        }
        *p = std::ptr::null_mut();
    }
    Ok(())
}

/// # Safety
/// `state` is null or a state this library made.
unsafe fn saved<'a>(state: *mut c_void) -> Fallible<&'a Snapshot> {
    (state as *const Snapshot)
        .as_ref()
        .ok_or_else(|| "FMUstate is a null pointer".into())
}

/// `serializedFMUstateSize`: the length of the state's bytes.
///
/// # Safety
/// `state` is null or a state this library made; `size` is null or writable.
pub unsafe fn serialized_size(i: &Instance, state: *mut c_void, size: *mut usize) -> Fallible<()> {
    let out = size.as_mut().ok_or("size is a null pointer")?;
    *out = serial::to_bytes(saved(state)?, &i.fingerprint).len();
    Ok(())
}

/// `serializeFMUstate`: the state's bytes into the host's buffer of `n` bytes.
///
/// # Safety
/// `state` is null or a state this library made; `bytes` is null or points to `n` writable bytes.
pub unsafe fn serialize(
    i: &Instance,
    state: *mut c_void,
    bytes: *mut u8,
    n: usize,
) -> Fallible<()> {
    let data = serial::to_bytes(saved(state)?, &i.fingerprint);
    if bytes.is_null() || n < data.len() {
        return Err(format!(
            "the buffer ({n} bytes) is smaller than the state ({} bytes)",
            data.len()
        ));
    }
    slice_mut(bytes, data.len()).copy_from_slice(&data);
    Ok(())
}

/// `deSerializeFMUstate`: a new saved state from `n` bytes (checked before anything is made).
///
/// # Safety
/// `bytes` is null or points to `n` bytes; `state` is null or points to null or to a state
/// this library made.
pub unsafe fn deserialize(
    i: &Instance,
    bytes: *const u8,
    n: usize,
    state: *mut *mut c_void,
) -> Fallible<()> {
    let out = state.as_mut().ok_or("FMUstate is a null pointer")?;
    if bytes.is_null() && n > 0 {
        return Err("the serialized state is a null pointer".into());
    }
    let snap = serial::from_bytes(slice(bytes, n), &i.fingerprint)?;
    match (*out as *mut Snapshot).as_mut() {
        Some(old) => *old = snap, // the host passed a state to reuse
        None => *out = Box::into_raw(Box::new(snap)) as *mut c_void,
    }
    Ok(())
}
