//! The C API called directly, as a host would, including what Python hosts cannot easily do:
//! null handles and pointers, a wrong instantiation token, a missing resource folder, every
//! truncation and flipped bit of a serialized state.

use std::ffi::{c_char, c_void, CStr, CString};
use std::ptr;

use stiction_fmi::fmi2::{fmi2DoStep, fmi2GetReal, fmi2Instantiate};
use stiction_fmi::fmi3::*;
use stiction_fmi::types::Status;

/// The host's logger: the instance environment is the test's own list of messages.
unsafe extern "C" fn logger(env: *mut c_void, _s: Status, _c: *const c_char, msg: *const c_char) {
    let text = CStr::from_ptr(msg).to_string_lossy().into_owned();
    (*(env as *mut Vec<String>)).push(text);
}

const MODEL: &str = r#"
name = "spin"
inputs = ["src.tau"]
connect = [["src.flange", "J.flange_a"]]
[experiment]
StopTime = 1.0
[components]
J = { type = "Inertia", J = 2.0, phi = 0.0, w = 0.0 }
src = { type = "Torque" }
"#;

fn resources(tag: &str) -> CString {
    let dir = std::env::temp_dir().join(format!("stiction-fmi-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("model.toml"), MODEL).unwrap();
    let table = "guid\ttoken\n0\tinput\tsrc.tau\t0.0\n1\toutput\tJ.w\t0\n2\tparameter\tJ.J\t2.0\n";
    std::fs::write(dir.join("variables.tsv"), table).unwrap();
    CString::new(dir.to_str().unwrap()).unwrap()
}

unsafe fn instantiate(token: &CStr, dir: &CStr, log: &mut Vec<String>) -> *mut c_void {
    let env = log as *mut Vec<String> as *mut c_void;
    let (name, none) = (c"t".as_ptr(), ptr::null());
    let (token, dir) = (token.as_ptr(), dir.as_ptr());
    let update = ptr::null_mut();
    fmi3InstantiateCoSimulation(
        name,
        token,
        dir,
        false,
        false,
        false,
        false,
        none,
        0,
        env,
        Some(logger),
        update,
    )
}

fn last(log: &[String]) -> &str {
    log.last().map(String::as_str).unwrap_or_default()
}

#[test]
fn null_handles_and_pointers_give_errors_not_crashes() {
    unsafe {
        assert_eq!(fmi2DoStep(ptr::null_mut(), 0.0, 0.1, 1), Status::Error);
        let status = fmi2GetReal(ptr::null_mut(), ptr::null(), 0, ptr::null_mut());
        assert_eq!(status, Status::Error);
        let (name, guid, dir) = (c"x".as_ptr(), c"g".as_ptr(), c"/nonexistent".as_ptr());
        assert!(fmi2Instantiate(name, 1, guid, dir, ptr::null(), 0, 0).is_null());
        fmi3FreeInstance(ptr::null_mut());
        let (dir, mut log) = (resources("null"), Vec::new());
        let c = instantiate(c"token", &dir, &mut log);
        assert!(!c.is_null());
        assert_eq!(fmi3GetFMUState(c, ptr::null_mut()), Status::Error);
        assert!(last(&log).contains("null pointer"), "{log:?}");
        fmi3FreeInstance(c);
    }
}

#[test]
fn a_wrong_token_or_folder_is_refused_with_a_message() {
    unsafe {
        let (dir, mut log) = (resources("token"), Vec::new());
        assert!(instantiate(c"other", &dir, &mut log).is_null());
        assert!(last(&log).contains("does not match"), "{log:?}");
        assert!(instantiate(c"token", c"/nonexistent/stiction", &mut log).is_null());
        assert!(last(&log).contains("cannot read"), "{log:?}");
    }
}

#[test]
fn a_torque_input_spins_the_inertia_as_newton_says() {
    unsafe {
        let (dir, mut log) = (resources("run"), Vec::new());
        let c = instantiate(c"token", &dir, &mut log);
        assert_eq!(
            fmi3EnterInitializationMode(c, false, 0.0, 0.0, true, 1.0),
            Status::Ok
        );
        assert_eq!(fmi3ExitInitializationMode(c), Status::Ok);
        let tau = [4.0];
        assert_eq!(
            fmi3SetFloat64(c, [0].as_ptr(), 1, tau.as_ptr(), 1),
            Status::Ok
        );
        let (mut event, mut stop, mut early, mut t) = (true, true, true, 0.0);
        // found by fuzzing: a NaN communication point was taken for the current time
        let nan = fmi3DoStep(
            c,
            f64::NAN,
            0.5,
            true,
            &mut event,
            &mut stop,
            &mut early,
            &mut t,
        );
        assert_eq!(nan, Status::Error);
        assert!(
            last(&log).contains("currentCommunicationPoint NaN"),
            "{log:?}"
        );
        let status = fmi3DoStep(c, 0.0, 0.5, true, &mut event, &mut stop, &mut early, &mut t);
        assert_eq!(status, Status::Ok);
        assert_eq!((event, stop, early, t), (false, false, false, 0.5));
        let mut w = [0.0];
        assert_eq!(
            fmi3GetFloat64(c, [1].as_ptr(), 1, w.as_mut_ptr(), 1),
            Status::Ok
        );
        assert!((w[0] - 4.0 / 2.0 * 0.5).abs() < 1e-9, "{}", w[0]);
        // J is tunable: 4 from now on, half the acceleration
        assert_eq!(
            fmi3SetFloat64(c, [2].as_ptr(), 1, tau.as_ptr(), 1),
            Status::Ok
        );
        let status = fmi3DoStep(c, 0.5, 0.5, true, &mut event, &mut stop, &mut early, &mut t);
        assert_eq!(status, Status::Ok);
        assert_eq!(
            fmi3GetFloat64(c, [1].as_ptr(), 1, w.as_mut_ptr(), 1),
            Status::Ok
        );
        assert!((w[0] - (1.0 + 4.0 / 4.0 * 0.5)).abs() < 1e-9, "{}", w[0]);
        // but not to zero: the shaft's speed would become algebraic
        let zero = [0.0];
        assert_eq!(
            fmi3SetFloat64(c, [2].as_ptr(), 1, zero.as_ptr(), 1),
            Status::Error
        );
        assert!(last(&log).contains("parameter 'J'"), "{log:?}");
        assert_eq!(fmi3Terminate(c), Status::Ok);
        fmi3FreeInstance(c);
    }
}

#[test]
fn every_truncation_and_every_flipped_bit_of_a_serialized_state_is_refused() {
    unsafe {
        let (dir, mut log) = (resources("bytes"), Vec::new());
        let c = instantiate(c"token", &dir, &mut log);
        assert_eq!(
            fmi3EnterInitializationMode(c, false, 0.0, 0.0, true, 1.0),
            Status::Ok
        );
        assert_eq!(fmi3ExitInitializationMode(c), Status::Ok);
        let (mut event, mut stop, mut early, mut t) = (false, false, false, 0.0);
        fmi3DoStep(
            c, 0.0, 0.25, true, &mut event, &mut stop, &mut early, &mut t,
        );
        let mut state = ptr::null_mut();
        assert_eq!(fmi3GetFMUState(c, &mut state), Status::Ok);
        let mut n = 0;
        assert_eq!(fmi3SerializedFMUStateSize(c, state, &mut n), Status::Ok);
        let mut bytes = vec![0u8; n];
        assert_eq!(
            fmi3SerializeFMUState(c, state, bytes.as_mut_ptr(), n),
            Status::Ok
        );
        assert_eq!(
            fmi3SerializeFMUState(c, state, bytes.as_mut_ptr(), n - 1),
            Status::Error // a buffer too small
        );
        let mut copy = ptr::null_mut();
        let deserialize = |b: &[u8], copy: &mut *mut c_void| {
            fmi3DeserializeFMUState(c, b.as_ptr(), b.len(), copy)
        };
        for k in 0..n {
            assert_eq!(
                deserialize(&bytes[..k], &mut copy),
                Status::Error,
                "{k} bytes"
            );
        }
        for bit in 0..8 * n {
            bytes[bit / 8] ^= 1 << (bit % 8);
            assert_eq!(deserialize(&bytes, &mut copy), Status::Error, "bit {bit}");
            bytes[bit / 8] ^= 1 << (bit % 8);
        }
        assert!(copy.is_null()); // nothing was made from bad bytes
        assert_eq!(deserialize(&bytes, &mut copy), Status::Ok);
        assert_eq!(fmi3SetFMUState(c, copy), Status::Ok);
        let mut again = vec![0u8; n];
        assert_eq!(
            fmi3SerializeFMUState(c, copy, again.as_mut_ptr(), n),
            Status::Ok
        );
        assert_eq!(again, bytes);
        fmi3FreeFMUState(c, &mut state);
        fmi3FreeFMUState(c, &mut copy);
        fmi3FreeInstance(c);
    }
}
