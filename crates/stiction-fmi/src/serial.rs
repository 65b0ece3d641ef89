//! The byte form of a saved FMU state (`fmi2SerializeFMUstate`, `fmi3SerializeFMUState`).
//!
//! Layout, little-endian: the magic `STICFMUS`, the format version (u32), the fingerprint of the
//! model (the FMU's GUID, itself a hash of the model and its variable table, and the runtime's
//! version, each a u32 length and UTF-8), the snapshot (every variable's values now and when
//! the run was built, the experiment, the run's input events and parameter changes and what it
//! reached), then an FNV-1a 64 checksum of all
//! that precedes it. Numbers are f64 bit patterns, so a restored state is the saved one exactly.
//!
//! Written by hand: the snapshot is a few vectors of plain fields, and a serialization crate
//! (serde + bincode/postcard) would add derive macros to stiction-core's types and several
//! crates to a build that is slow on small machines, for about the same number of lines here.
//! Every read is bounds-checked and every length is checked against the bytes left, so
//! truncated or corrupted bytes give an error (never a panic or a huge allocation).

use stiction_core::Discrete;
use stiction_core::DiscreteState;
use stiction_core::SwitchState;
use stiction_core::{Cursor, InputChange, ParameterChange, SimState};
use stiction_core::{RelationSet, MAX_RELATIONS};

use crate::instance::{Experiment, Fallible, Snapshot};

const MAGIC: &[u8; 8] = b"STICFMUS";
/// 3: the parameter changes of step mode and the values the run was built with; 2: the run's
/// input events (a restored state replays them) and the values of array and Boolean
/// variables; 1 had the integrator's step size.
const VERSION: u32 = 3;

/// What a state must have been saved with to be restored here.
pub fn fingerprint(guid: &str) -> String {
    format!("{guid} stiction-fmi {}", env!("CARGO_PKG_VERSION"))
}

/// FNV-1a, 64 bits: enough to notice corrupted bytes (not an adversary).
fn checksum(bytes: &[u8]) -> u64 {
    (bytes.iter()).fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The bytes of `snap`, saved by the model with fingerprint `model`.
pub fn to_bytes(snap: &Snapshot, model: &str) -> Vec<u8> {
    let mut w = Writer(Vec::with_capacity(256));
    w.0.extend_from_slice(MAGIC);
    w.u32(VERSION);
    w.text(model);
    for values in [&snap.values, &snap.base] {
        w.count(values.len());
        values.iter().for_each(|v| w.floats(v));
    }
    for v in [
        snap.experiment.start,
        snap.experiment.stop,
        snap.experiment.tolerance,
    ] {
        w.option(v);
    }
    w.sim(&snap.sim);
    let sum = checksum(&w.0);
    w.u64(sum);
    w.0
}

/// The snapshot in `bytes`; an error names what is wrong with them.
pub fn from_bytes(bytes: &[u8], model: &str) -> Fallible<Snapshot> {
    let bad = |what: &str| format!("the serialized FMU state is not valid: {what}");
    if bytes.len() < MAGIC.len() + 12 || &bytes[..MAGIC.len()] != MAGIC {
        return Err(bad("it is not a stiction FMU state"));
    }
    let (body, sum) = bytes.split_at(bytes.len() - 8);
    if checksum(body).to_le_bytes() != sum {
        return Err(bad(
            "its checksum does not match (truncated or corrupted bytes)",
        ));
    }
    let mut r = Reader(&body[MAGIC.len()..]);
    let version = r.u32()?;
    if version != VERSION {
        return Err(bad(&format!(
            "format version {version}, this FMU reads {VERSION}"
        )));
    }
    let saved_by = r.text()?;
    if saved_by != model {
        return Err(bad(&format!(
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
    let sim = r.sim()?;
    if !r.0.is_empty() {
        return Err(bad("bytes left over after the state"));
    }
    Ok(Snapshot {
        sim,
        values,
        base,
        experiment,
    })
}

struct Writer(Vec<u8>);

impl Writer {
    fn u32(&mut self, v: u32) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn u64(&mut self, v: u64) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn f64(&mut self, v: f64) {
        self.u64(v.to_bits());
    }
    fn flag(&mut self, v: bool) {
        self.0.push(v as u8);
    }
    fn count(&mut self, n: usize) {
        self.u32(u32::try_from(n).expect("fewer than 2³² items"));
    }
    fn text(&mut self, s: &str) {
        self.count(s.len());
        self.0.extend_from_slice(s.as_bytes());
    }
    fn floats(&mut self, v: &[f64]) {
        self.count(v.len());
        v.iter().for_each(|&x| self.f64(x));
    }
    fn option(&mut self, v: Option<f64>) {
        self.flag(v.is_some());
        self.f64(v.unwrap_or(0.0));
    }
    fn sim(&mut self, s: &SimState) {
        self.floats(&s.x);
        self.count(s.disc.switching.len());
        for e in &s.disc.switching {
            self.0.push(e.pre.mode as u8);
            for b in [e.pre.start_forward, e.pre.start_backward, e.locked, e.free] {
                self.flag(b);
            }
            e.rel.0.iter().for_each(|&b| self.flag(b));
        }
        self.count(s.disc.relations.len());
        s.disc.relations.iter().for_each(|&b| self.flag(b));
        self.floats(&s.disc.inputs);
        self.f64(s.horizon);
        let c = &s.cursor;
        self.f64(c.now);
        self.f64(c.stop);
        self.u64(c.next_te as u64);
        self.u64(c.grid_k as u64);
        self.flag(c.finished);
        self.count(s.inputs.len());
        for change in &s.inputs {
            self.f64(change.time);
            self.u64(change.input as u64);
            self.f64(change.value);
        }
        self.count(s.parameters.len());
        for change in &s.parameters {
            self.f64(change.time);
            self.u64(change.after_inputs as u64);
            self.count(change.values.len());
            for (name, value) in &change.values {
                self.text(name);
                self.value(value);
            }
        }
    }
    /// A model-file value: a tag, then the number, flag, text or items.
    fn value(&mut self, v: &toml::Value) {
        match v {
            toml::Value::Float(x) => {
                self.0.push(0);
                self.f64(*x);
            }
            toml::Value::Integer(i) => {
                self.0.push(1);
                self.u64(*i as u64);
            }
            toml::Value::Boolean(b) => {
                self.0.push(2);
                self.flag(*b);
            }
            toml::Value::Array(items) => {
                self.0.push(3);
                self.count(items.len());
                items.iter().for_each(|item| self.value(item));
            }
            toml::Value::Table(t) => {
                self.0.push(4);
                self.count(t.len());
                for (key, item) in t {
                    self.text(key);
                    self.value(item);
                }
            }
            other => {
                self.0.push(5);
                self.text(&other.to_string());
            }
        }
    }
}

struct Reader<'a>(&'a [u8]);

impl Reader<'_> {
    fn take(&mut self, n: usize) -> Fallible<&[u8]> {
        if n > self.0.len() {
            return Err("the serialized FMU state is not valid: it ends too early".into());
        }
        let (head, rest) = self.0.split_at(n);
        self.0 = rest;
        Ok(head)
    }
    fn array<const N: usize>(&mut self) -> Fallible<[u8; N]> {
        Ok(self.take(N)?.try_into().expect("N bytes taken"))
    }
    fn u8(&mut self) -> Fallible<u8> {
        Ok(self.take(1)?[0])
    }
    fn u32(&mut self) -> Fallible<u32> {
        Ok(u32::from_le_bytes(self.array()?))
    }
    fn u64(&mut self) -> Fallible<u64> {
        Ok(u64::from_le_bytes(self.array()?))
    }
    fn usize(&mut self) -> Fallible<usize> {
        usize::try_from(self.u64()?)
            .map_err(|_| "the serialized FMU state is not valid: a count out of range".into())
    }
    fn f64(&mut self) -> Fallible<f64> {
        Ok(f64::from_bits(self.u64()?))
    }
    fn flag(&mut self) -> Fallible<bool> {
        match self.u8()? {
            0 => Ok(false),
            1 => Ok(true),
            b => Err(format!(
                "the serialized FMU state is not valid: {b} is not a Boolean"
            )),
        }
    }
    /// A count of items of at least `size` bytes each, no more than the bytes left can hold.
    fn count(&mut self, size: usize) -> Fallible<usize> {
        let n = self.u32()? as usize;
        if n.saturating_mul(size) > self.0.len() {
            return Err("the serialized FMU state is not valid: it ends too early".into());
        }
        Ok(n)
    }
    fn text(&mut self) -> Fallible<String> {
        let n = self.count(1)?;
        String::from_utf8(self.take(n)?.to_vec())
            .map_err(|_| "the serialized FMU state is not valid: a name is not UTF-8".into())
    }
    fn floats(&mut self) -> Fallible<Vec<f64>> {
        let n = self.count(8)?;
        (0..n).map(|_| self.f64()).collect()
    }
    fn option(&mut self) -> Fallible<Option<f64>> {
        let (some, v) = (self.flag()?, self.f64()?);
        Ok(some.then_some(v))
    }
    fn element(&mut self) -> Fallible<SwitchState> {
        let mode = self.u8()? as i8;
        let [start_forward, start_backward, locked, free] =
            [self.flag()?, self.flag()?, self.flag()?, self.flag()?];
        let mut rel = [false; MAX_RELATIONS];
        for r in &mut rel {
            *r = self.flag()?;
        }
        Ok(SwitchState {
            pre: Discrete {
                mode,
                start_forward,
                start_backward,
            },
            locked,
            free,
            rel: RelationSet(rel),
        })
    }
    fn input_change(&mut self) -> Fallible<InputChange> {
        Ok(InputChange {
            time: self.f64()?,
            input: self.usize()?,
            value: self.f64()?,
        })
    }
    fn parameter_change(&mut self) -> Fallible<ParameterChange> {
        let (time, after_inputs) = (self.f64()?, self.usize()?);
        let n = self.count(6)?;
        let values = (0..n)
            .map(|_| Ok((self.text()?, self.value(0)?)))
            .collect::<Fallible<_>>()?;
        Ok(ParameterChange {
            time,
            after_inputs,
            values,
        })
    }
    /// A model-file value (`Writer::value`), nested at most a few levels as tables are.
    fn value(&mut self, depth: usize) -> Fallible<toml::Value> {
        if depth > 8 {
            return Err("the serialized FMU state is not valid: values nested too deep".into());
        }
        Ok(match self.u8()? {
            0 => toml::Value::Float(self.f64()?),
            1 => toml::Value::Integer(self.u64()? as i64),
            2 => toml::Value::Boolean(self.flag()?),
            3 => {
                let n = self.count(1)?;
                let items = (0..n).map(|_| self.value(depth + 1));
                toml::Value::Array(items.collect::<Fallible<_>>()?)
            }
            4 => {
                let n = self.count(5)?;
                let mut t = toml::Table::new();
                for _ in 0..n {
                    let key = self.text()?;
                    t.insert(key, self.value(depth + 1)?);
                }
                toml::Value::Table(t)
            }
            5 => toml::Value::String(self.text()?),
            tag => {
                return Err(format!(
                    "the serialized FMU state is not valid: value tag {tag}"
                ))
            }
        })
    }
    fn sim(&mut self) -> Fallible<SimState> {
        let x = self.floats()?;
        let n = self.count(5 + MAX_RELATIONS)?;
        let switching = (0..n).map(|_| self.element()).collect::<Fallible<_>>()?;
        let n = self.count(1)?;
        let relations = (0..n).map(|_| self.flag()).collect::<Fallible<_>>()?;
        let inputs = self.floats()?;
        let horizon = self.f64()?;
        let cursor = Cursor {
            now: self.f64()?,
            stop: self.f64()?,
            next_te: self.usize()?,
            grid_k: self.usize()?,
            finished: self.flag()?,
        };
        let n = self.count(24)?;
        let changes = (0..n)
            .map(|_| self.input_change())
            .collect::<Fallible<_>>()?;
        let n = self.count(20)?;
        let parameters = (0..n)
            .map(|_| self.parameter_change())
            .collect::<Fallible<_>>()?;
        Ok(SimState {
            inputs: changes,
            parameters,
            x,
            disc: DiscreteState {
                switching,
                relations,
                inputs,
            },
            horizon,
            cursor,
        })
    }
}
