//! The byte form of a saved FMU state (`fmi2SerializeFMUstate`, `fmi3SerializeFMUState`).
//!
//! Layout, little-endian, framed by the core's `ByteWriter` (the same bytes Python pickles a
//! `SimulationState` with): the magic `STICFMUS`, the format version (u32), the fingerprint of
//! the model (the FMU's GUID, itself a hash of the model and its variable table, and the
//! runtime's version, a u32 length and UTF-8), every variable's values now and when the run
//! was built, the experiment, then the run's state as the core writes it
//! (`ByteWriter::state`: its input events and parameter changes and what it reached), then an
//! FNV-1a 64 checksum of all that precedes it. Numbers are f64 bit patterns, so a restored
//! state is the saved one exactly; truncated or corrupted bytes give an error.

use stiction_core::{ByteReader, ByteWriter, STATE_BYTES_VERSION};

use crate::snapshot::{Experiment, Fallible, Snapshot};

const MAGIC: &[u8; 8] = b"STICFMUS";
/// The version of this format: the core's state bytes (`STATE_BYTES_VERSION`) with the
/// values and the experiment around them. 3: the parameter changes of step mode and the values
/// the run was built with; 2: the run's input events (a restored state replays them) and the
/// values of array and Boolean variables; 1 had the integrator's step size.
const VERSION: u32 = 3;
// The run's bytes are the core's: when they change (a new STATE_BYTES_VERSION), so does this
// format. Bump VERSION with it, and this check.
const _: () = assert!(
    STATE_BYTES_VERSION == 3,
    "bump the FMU's VERSION with the core's"
);

const WHAT: &str = "the serialized FMU state";

/// The bytes of `snap`, saved by the model with fingerprint `model`.
pub fn to_bytes(snap: &Snapshot, model: &str) -> Vec<u8> {
    let mut w = ByteWriter::new(MAGIC, VERSION);
    w.text(model);
    for values in [&snap.values, &snap.base] {
        w.count(values.len());
        values.iter().for_each(|v| w.floats(v));
    }
    let e = &snap.experiment;
    for v in [e.start, e.stop, e.tolerance] {
        w.option(v);
    }
    w.state(&snap.sim);
    w.finish()
}

/// The snapshot in `bytes`; an error names what is wrong with them.
pub fn from_bytes(bytes: &[u8], model: &str) -> Fallible<Snapshot> {
    let (mut r, version) = ByteReader::open(bytes, MAGIC, WHAT, "a stiction FMU state")?;
    if version != VERSION {
        return Err(r.bad(&format!(
            "format version {version}, this FMU reads {VERSION}"
        )));
    }
    let saved_by = r.text()?;
    if saved_by != model {
        return Err(r.bad(&format!(
            "it was saved by another model or runtime ({saved_by}), this is {model}"
        )));
    }
    let n = r.count(4)?;
    let values = (0..n).map(|_| r.floats()).collect::<Fallible<_>>()?;
    let n = r.count(4)?;
    let base = (0..n).map(|_| r.floats()).collect::<Fallible<_>>()?;
    let experiment = Experiment {
        start: r.option()?,
        stop: r.option()?,
        tolerance: r.option()?,
    };
    let sim = r.state()?;
    r.end()?;
    Ok(Snapshot {
        sim,
        values,
        base,
        experiment,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use stiction_core::{ModelSpec, SimState, Simulation};

    /// A state of CoupledClutches a second in.
    fn state() -> SimState {
        let text = include_str!("../../../examples/msl/CoupledClutches.toml");
        let spec = ModelSpec::from_toml(text, ".").expect("the model parses");
        let mut sim = Simulation::from_spec(&spec).expect("it builds");
        sim.advance_to(1.0).expect("it runs");
        sim.state().expect("a state")
    }

    /// The FMU's bytes hold the run's state exactly as the core writes it for Python's pickles
    /// (the body of `SimState::to_bytes`, between its magic and version and its checksum), and
    /// read back to the same snapshot.
    #[test]
    fn the_fmu_state_carries_the_cores_state_bytes() {
        let sim = state();
        let snap = Snapshot {
            sim: sim.clone(),
            values: vec![vec![1.0, 2.0], vec![]],
            base: vec![vec![0.5]],
            experiment: Experiment {
                start: Some(0.0),
                stop: None,
                tolerance: Some(1e-6),
            },
        };
        let bytes = to_bytes(&snap, "model");
        let core = sim.to_bytes();
        let body = &core[12..core.len() - 8];
        assert!(bytes[..bytes.len() - 8].ends_with(body));
        let back = from_bytes(&bytes, "model").expect("reads back");
        assert_eq!(back.sim, sim);
        assert_eq!((back.values, back.base), (snap.values, snap.base));
        assert_eq!(back.experiment, snap.experiment);
        let other = from_bytes(&bytes, "another")
            .err()
            .expect("another model's state");
        assert!(other.contains("saved by another model"), "{other}");
    }
}
