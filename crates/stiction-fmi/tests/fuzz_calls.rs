//! Fuzzing the FMI calls (proptest): random sequences of what a host may do, in any order and
//! with any arguments — initialization out of order, value references out of range, non-finite
//! and extreme values, steps that are negative, zero, huge or not at the current time, resets,
//! terminations, saved states set, freed and (de)serialized with their bytes cut or flipped —
//! against a braked flywheel with two inputs, in FMI 3.0 (with a logger) and FMI 2.0 (without).
//!
//! Whatever the host does, every call returns a status and never crashes, panics or hangs (a
//! watchdog fails the case when one call takes over 20 s); in FMI 3.0 every error status comes
//! with a logged message, and values read with status OK are finite. CI runs the default budget;
//! `PROPTEST_CASES=20000 cargo test --release -p stiction-fmi --test fuzz_calls` runs a long
//! campaign.

use std::ffi::{c_char, c_void, CStr, CString};
use std::ptr;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, OnceLock};
use std::time::{Duration, Instant};

use proptest::prelude::*;
use stiction_fmi::fmi2::*;
use stiction_fmi::fmi3::*;
use stiction_fmi::types::{CallbackFunctions, Status};

const MODEL: &str = r#"
name = "braked"
inputs = ["brake.f_normalized", "src.tau"]
connect = [["src.flange", "J.flange_a"], ["J.flange_b", "brake.flange_a"]]
[experiment]
StopTime = 10.0
[components]
J = { type = "Inertia", J = 2.0, phi = 0.0, w = 5.0 }
src = { type = "Torque" }
brake = { type = "Brake", fn_max = 50.0 }
"#;
const TABLE: &str = "guid\ttoken\n0\tinput\tbrake.f_normalized\t0.0\n1\tinput\tsrc.tau\t0.0\n\
2\toutput\tbrake.mode\t0\n3\tstart\tJ.w\t5.0\n4\tparameter\tJ.J\t2.0\n5\tparameter\tbrake.fn_max\t50.0\n";
/// Value references 0–5 exist; 6 and the largest do not.
const REFS: [u32; 8] = [0, 1, 2, 3, 4, 5, 6, u32::MAX];

/// The FMU's resource folder, one per test (the tests run in parallel threads).
fn resources(tag: &str) -> CString {
    let dir = std::env::temp_dir().join(format!("stiction-fmi-fuzz-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("model.toml"), MODEL).unwrap();
    std::fs::write(dir.join("variables.tsv"), TABLE).unwrap();
    CString::new(dir.to_str().unwrap()).unwrap()
}

#[derive(Debug, Clone)]
enum Call {
    Setup {
        stop: Option<f64>,
    },
    EnterInit,
    ExitInit,
    Set(u32, f64),
    Get(u32),
    /// A step of `h` from the current time, or from `at` when given.
    Step {
        at: Option<f64>,
        h: f64,
    },
    Reset,
    Terminate,
    SaveState,
    RestoreState(usize),
    FreeState(usize),
    /// Serialize a saved state, cut its bytes to `keep` of their length, flip bit `flip`, read
    /// them back.
    RoundTrip {
        state: usize,
        keep: f64,
        flip: Option<usize>,
    },
}

fn value() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -2.0..2.0f64,
        1 => prop::sample::select(vec![0.0, -0.0, 1e-300, 1e300, -1e300, f64::NAN, f64::INFINITY, f64::NEG_INFINITY]),
    ]
}

fn step() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => 1e-4..0.5f64,
        1 => prop::sample::select(vec![0.0, -0.1, 1e-300, 30.0, 1e300, f64::NAN, f64::INFINITY]),
    ]
}

fn call() -> impl Strategy<Value = Call> {
    let vr = prop::sample::select(REFS.to_vec());
    prop_oneof![
        1 => prop::option::of(prop::sample::select(vec![5.0, 10.0, -1.0, f64::NAN])).prop_map(|stop| Call::Setup { stop }),
        2 => Just(Call::EnterInit),
        2 => Just(Call::ExitInit),
        4 => (vr.clone(), value()).prop_map(|(r, v)| Call::Set(r, v)),
        3 => vr.prop_map(Call::Get),
        8 => (prop::option::of(prop::sample::select(vec![0.0, 0.5, -1.0, f64::NAN])), step())
            .prop_map(|(at, h)| Call::Step { at, h }),
        1 => Just(Call::Reset),
        1 => Just(Call::Terminate),
        2 => Just(Call::SaveState),
        2 => (0..4usize).prop_map(Call::RestoreState),
        1 => (0..4usize).prop_map(Call::FreeState),
        2 => (0..4usize, 0.0..1.2f64, prop::option::of(0..4096usize))
            .prop_map(|(state, keep, flip)| Call::RoundTrip { state, keep, flip }),
    ]
}

/// When the call under way started (ms since `origin()`, 0: none) and what it is; a watchdog
/// thread aborts the test binary, naming the call, when one has not returned for 20 s — a hang.
static CALL_STARTED: AtomicU64 = AtomicU64::new(0);
static CALL: Mutex<String> = Mutex::new(String::new());

fn origin() -> Instant {
    static ORIGIN: OnceLock<Instant> = OnceLock::new();
    *ORIGIN.get_or_init(|| {
        std::thread::spawn(|| loop {
            std::thread::sleep(Duration::from_millis(200));
            let since = CALL_STARTED.load(Ordering::Relaxed);
            if since > 0 && now_ms() - since > 20_000 {
                let call = CALL.lock().map(|c| c.clone()).unwrap_or_default();
                eprintln!("an FMI call has not returned for 20 s, a hang: {call}");
                std::process::abort();
            }
        });
        Instant::now()
    })
}

fn now_ms() -> u64 {
    origin().elapsed().as_millis() as u64 + 1
}

fn guarded<T>(call: &Call, history: &[Call], f: impl FnOnce() -> T) -> T {
    if let Ok(mut c) = CALL.lock() {
        *c = format!("{call:?} after {history:?}");
    }
    CALL_STARTED.store(now_ms(), Ordering::Relaxed);
    let out = f();
    CALL_STARTED.store(0, Ordering::Relaxed);
    out
}

/// The functions one FMI version offers, so that one interpreter drives both.
trait Host {
    unsafe fn run(&mut self, call: &Call) -> Status;
    fn logged_since(&mut self) -> bool;
    fn free(&mut self);
}

struct Fmi3 {
    c: *mut c_void,
    // boxed: the host's logger gets this list's address, which must not move with `Fmi3`
    #[allow(clippy::box_collection)]
    log: Box<Vec<String>>,
    seen: usize,
    states: Vec<*mut c_void>,
    time: f64,
}

unsafe extern "C" fn logger3(env: *mut c_void, _s: Status, _c: *const c_char, msg: *const c_char) {
    let text = CStr::from_ptr(msg).to_string_lossy().into_owned();
    (*(env as *mut Vec<String>)).push(text);
}

impl Fmi3 {
    unsafe fn new(dir: &CStr) -> Self {
        let mut log = Box::new(Vec::new());
        let env = &mut *log as *mut Vec<String> as *mut c_void;
        let c = fmi3InstantiateCoSimulation(
            c"fuzz".as_ptr(),
            c"token".as_ptr(),
            dir.as_ptr(),
            false,
            false,
            false,
            false,
            ptr::null(),
            0,
            env,
            Some(logger3),
            ptr::null_mut(),
        );
        assert!(!c.is_null(), "{log:?}");
        Self {
            c,
            log,
            seen: 0,
            states: Vec::new(),
            time: 0.0,
        }
    }
}

impl Host for Fmi3 {
    unsafe fn run(&mut self, call: &Call) -> Status {
        let c = self.c;
        match *call {
            Call::Setup { stop } => {
                fmi3EnterInitializationMode(c, false, 0.0, 0.0, stop.is_some(), stop.unwrap_or(0.0))
            }
            Call::EnterInit => fmi3EnterInitializationMode(c, true, 1e-6, 0.0, false, 0.0),
            Call::ExitInit => fmi3ExitInitializationMode(c),
            Call::Set(vr, v) => fmi3SetFloat64(c, [vr].as_ptr(), 1, [v].as_ptr(), 1),
            Call::Get(vr) => get_checked(|out| fmi3GetFloat64(c, [vr].as_ptr(), 1, out, 1)),
            Call::Step { at, h } => {
                let (mut event, mut stop, mut early, mut t) = (false, false, false, 0.0);
                let from = at.unwrap_or(self.time);
                let status =
                    fmi3DoStep(c, from, h, true, &mut event, &mut stop, &mut early, &mut t);
                if status == Status::Ok {
                    assert!(t.is_finite() && t >= from, "the step ended at {t}");
                    self.time = t;
                }
                status
            }
            Call::Reset => {
                self.time = 0.0;
                fmi3Reset(c)
            }
            Call::Terminate => fmi3Terminate(c),
            Call::SaveState => {
                let mut s = ptr::null_mut();
                let status = fmi3GetFMUState(c, &mut s);
                if status == Status::Ok {
                    self.states.push(s);
                }
                status
            }
            Call::RestoreState(k) => match self.states.get(k) {
                Some(&s) => fmi3SetFMUState(c, s),
                None => fmi3SetFMUState(c, ptr::null_mut()),
            },
            Call::FreeState(k) if k < self.states.len() => {
                let mut s = self.states.remove(k);
                fmi3FreeFMUState(c, &mut s)
            }
            Call::FreeState(_) => fmi3FreeFMUState(c, ptr::null_mut()),
            Call::RoundTrip { state, keep, flip } => {
                let Some(&s) = self.states.get(state) else {
                    return Status::Ok;
                };
                let mut size = 0usize;
                let status = fmi3SerializedFMUStateSize(c, s, &mut size);
                if status != Status::Ok {
                    return status;
                }
                let mut bytes = vec![0u8; size];
                let status = fmi3SerializeFMUState(c, s, bytes.as_mut_ptr(), size);
                if status != Status::Ok {
                    return status;
                }
                let bytes = mutate(bytes, keep, flip);
                let mut back = ptr::null_mut();
                let status = fmi3DeserializeFMUState(c, bytes.as_ptr(), bytes.len(), &mut back);
                if status == Status::Ok {
                    self.states.push(back);
                }
                status
            }
        }
    }

    fn logged_since(&mut self) -> bool {
        let grew = self.log.len() > self.seen;
        self.seen = self.log.len();
        grew
    }

    fn free(&mut self) {
        unsafe {
            for mut s in self.states.drain(..) {
                fmi3FreeFMUState(self.c, &mut s);
            }
            fmi3FreeInstance(self.c);
        }
    }
}

struct Fmi2 {
    c: *mut c_void,
    states: Vec<*mut c_void>,
    time: f64,
}

impl Fmi2 {
    unsafe fn new(dir: &CStr) -> Self {
        let callbacks = CallbackFunctions {
            logger: None,
            allocate_memory: None,
            free_memory: None,
            step_finished: None,
            component_environment: ptr::null_mut(),
        };
        let c = fmi2Instantiate(
            c"fuzz".as_ptr(),
            1,
            c"token".as_ptr(),
            dir.as_ptr(),
            &callbacks,
            0,
            0,
        );
        assert!(!c.is_null());
        Self {
            c,
            states: Vec::new(),
            time: 0.0,
        }
    }
}

impl Host for Fmi2 {
    unsafe fn run(&mut self, call: &Call) -> Status {
        let c = self.c;
        match *call {
            Call::Setup { stop } => {
                fmi2SetupExperiment(c, 0, 0.0, 0.0, stop.is_some() as i32, stop.unwrap_or(0.0))
            }
            Call::EnterInit => fmi2EnterInitializationMode(c),
            Call::ExitInit => fmi2ExitInitializationMode(c),
            Call::Set(vr, v) => fmi2SetReal(c, [vr].as_ptr(), 1, [v].as_ptr()),
            Call::Get(vr) => get_checked(|out| fmi2GetReal(c, [vr].as_ptr(), 1, out)),
            Call::Step { at, h } => {
                let from = at.unwrap_or(self.time);
                let status = fmi2DoStep(c, from, h, 1);
                if status == Status::Ok {
                    self.time = from + h;
                }
                status
            }
            Call::Reset => {
                self.time = 0.0;
                fmi2Reset(c)
            }
            Call::Terminate => fmi2Terminate(c),
            Call::SaveState => {
                let mut s = ptr::null_mut();
                let status = fmi2GetFMUstate(c, &mut s);
                if status == Status::Ok {
                    self.states.push(s);
                }
                status
            }
            Call::RestoreState(k) => {
                fmi2SetFMUstate(c, self.states.get(k).copied().unwrap_or(ptr::null_mut()))
            }
            Call::FreeState(k) if k < self.states.len() => {
                let mut s = self.states.remove(k);
                fmi2FreeFMUstate(c, &mut s)
            }
            Call::FreeState(_) => fmi2FreeFMUstate(c, ptr::null_mut()),
            Call::RoundTrip { state, keep, flip } => {
                let Some(&s) = self.states.get(state) else {
                    return Status::Ok;
                };
                let mut size = 0usize;
                let status = fmi2SerializedFMUstateSize(c, s, &mut size);
                if status != Status::Ok {
                    return status;
                }
                let mut bytes = vec![0u8; size];
                let status = fmi2SerializeFMUstate(c, s, bytes.as_mut_ptr() as *mut c_char, size);
                if status != Status::Ok {
                    return status;
                }
                let bytes = mutate(bytes, keep, flip);
                let mut back = ptr::null_mut();
                let status = fmi2DeSerializeFMUstate(
                    c,
                    bytes.as_ptr() as *const c_char,
                    bytes.len(),
                    &mut back,
                );
                if status == Status::Ok {
                    self.states.push(back);
                }
                status
            }
        }
    }

    fn logged_since(&mut self) -> bool {
        true // no logger: FMI 2.0 hosts without one are allowed
    }

    fn free(&mut self) {
        unsafe {
            for mut s in self.states.drain(..) {
                fmi2FreeFMUstate(self.c, &mut s);
            }
            fmi2FreeInstance(self.c);
        }
    }
}

/// A value read with status OK is finite.
fn get_checked(get: impl FnOnce(*mut f64) -> Status) -> Status {
    let mut out = f64::NAN;
    let status = get(&mut out);
    if status == Status::Ok {
        assert!(out.is_finite(), "a value read with status OK is {out}");
    }
    status
}

fn mutate(mut bytes: Vec<u8>, keep: f64, flip: Option<usize>) -> Vec<u8> {
    if keep < 1.0 {
        bytes.truncate((bytes.len() as f64 * keep) as usize);
    }
    if let Some(bit) = flip.filter(|&b| b / 8 < bytes.len()) {
        bytes[bit / 8] ^= 1 << (bit % 8);
    }
    bytes
}

fn drive(host: &mut dyn Host, calls: &[Call]) {
    for (k, call) in calls.iter().enumerate() {
        let status = guarded(call, &calls[..k], || unsafe { host.run(call) });
        assert!(
            matches!(
                status,
                Status::Ok | Status::Warning | Status::Discard | Status::Error
            ),
            "{call:?}: {status:?}"
        );
        let logged = host.logged_since();
        if status == Status::Error {
            assert!(logged, "{call:?} returned an error without a message");
        }
    }
    host.free();
}

/// Random calls, most often after a correct start (setup, initialization) so that steps,
/// inputs and saved states are exercised in step mode too, not only refused before it.
fn session() -> impl Strategy<Value = Vec<Call>> {
    let start = [Call::Setup { stop: None }, Call::EnterInit, Call::ExitInit];
    (
        prop::bool::weighted(0.8),
        prop::collection::vec(call(), 1..40),
    )
        .prop_map(move |(started, calls)| match started {
            true => start.iter().cloned().chain(calls).collect(),
            false => calls,
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    #[test]
    fn any_sequence_of_fmi3_calls_answers_with_a_status(calls in session()) {
        let dir = resources("fmi3");
        let mut host = unsafe { Fmi3::new(&dir) };
        drive(&mut host, &calls);
    }

    #[test]
    fn any_sequence_of_fmi2_calls_answers_with_a_status(calls in session()) {
        let dir = resources("fmi2");
        let mut host = unsafe { Fmi2::new(&dir) };
        drive(&mut host, &calls);
    }
}
