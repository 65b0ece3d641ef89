//! The byte form of a saved run (`SimState`): the one format the FMU's serialized states
//! (`fmi2SerializeFMUstate`, `fmi3SerializeFMUState`, which wrap it with the model's values)
//! and Python's pickled `SimulationState` (`SimState::to_bytes`) both write, so a change of the
//! engine's state changes both at once, under one version number.
//!
//! Little-endian throughout; numbers are f64 bit patterns, so a restored state is the saved one
//! exactly. A file of bytes is framed (`ByteWriter::new`, `finish`): an 8-byte magic, the
//! format version (u32), the body, then an FNV-1a 64 checksum of all that precedes it. The
//! state itself (`ByteWriter::state`) is what the run reached (`x`, the discrete state, the
//! horizon, the cursor), its input events and its parameter changes (values tagged as the
//! model file writes them).
//!
//! Written by hand: the state is a few vectors of plain fields, and a serialization crate
//! (serde + bincode/postcard) would add derive macros to the core's types and several crates
//! to a build that is slow on small machines, for about the same number of lines here. Every
//! read is bounds-checked and every length is checked against the bytes left, so truncated or
//! corrupted bytes give an error (never a panic or a huge allocation).

use super::{Cursor, InputChange, ParameterChange, SimState};
use crate::engine::eval::DiscreteState;
use crate::error::SimError;
use crate::switching::element::SwitchState;
use crate::switching::logic::Discrete;
use crate::switching::relation::{RelationSet, MAX_RELATIONS};

/// The version of the state's bytes: bump it with any change to what `ByteWriter::state`
/// writes (the test `state_bytes_are_pinned` holds the bytes of one state). The FMU's format
/// carries it. 3: parameter changes (and the FMU's values the run was built with); 2: input
/// events (a restored state replays them) and the values of array and Boolean variables; 1 had
/// the integrator's step size.
pub const STATE_BYTES_VERSION: u32 = 3;

/// The magic of `SimState::to_bytes`.
const MAGIC: &[u8; 8] = b"STICSIMS";

/// What goes wrong reading bytes: the message, already saying which bytes they are.
pub type ReadResult<T> = Result<T, String>;

/// FNV-1a, 64 bits: enough to notice corrupted bytes (not an adversary).
fn checksum(bytes: &[u8]) -> u64 {
    (bytes.iter()).fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

impl SimState {
    /// The state as bytes on their own (magic `STICSIMS`, `STATE_BYTES_VERSION`, the state, a
    /// checksum): what Python pickles.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut w = ByteWriter::new(MAGIC, STATE_BYTES_VERSION);
        w.state(self);
        w.finish()
    }

    /// The state in bytes from `to_bytes`; a usage error says what is wrong with them.
    pub fn from_bytes(bytes: &[u8]) -> Result<SimState, SimError> {
        let read = || -> ReadResult<SimState> {
            let what = "the saved simulation state";
            let (mut r, version) = ByteReader::open(bytes, MAGIC, what, "a stiction state")?;
            if version != STATE_BYTES_VERSION {
                let reads = STATE_BYTES_VERSION;
                return Err(r.bad(&format!(
                    "format version {version}, this build reads {reads}"
                )));
            }
            let state = r.state()?;
            r.end()?;
            Ok(state)
        };
        read().map_err(SimError::Usage)
    }
}

/// Writes framed bytes: `new` puts the magic and the version, `finish` the checksum.
pub struct ByteWriter(Vec<u8>);

impl ByteWriter {
    pub fn new(magic: &[u8; 8], version: u32) -> Self {
        let mut w = Self(Vec::with_capacity(256));
        w.0.extend_from_slice(magic);
        w.u32(version);
        w
    }
    /// The bytes, with the checksum of everything written appended.
    pub fn finish(mut self) -> Vec<u8> {
        let sum = checksum(&self.0);
        self.u64(sum);
        self.0
    }
    pub fn u32(&mut self, v: u32) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    pub fn u64(&mut self, v: u64) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    pub fn f64(&mut self, v: f64) {
        self.u64(v.to_bits());
    }
    pub fn flag(&mut self, v: bool) {
        self.0.push(v as u8);
    }
    pub fn count(&mut self, n: usize) {
        self.u32(u32::try_from(n).expect("fewer than 2³² items"));
    }
    pub fn text(&mut self, s: &str) {
        self.count(s.len());
        self.0.extend_from_slice(s.as_bytes());
    }
    pub fn floats(&mut self, v: &[f64]) {
        self.count(v.len());
        v.iter().for_each(|&x| self.f64(x));
    }
    pub fn option(&mut self, v: Option<f64>) {
        self.flag(v.is_some());
        self.f64(v.unwrap_or(0.0));
    }
    /// A saved run.
    pub fn state(&mut self, s: &SimState) {
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

/// Reads framed bytes back; every error names the bytes (`what`) and what is wrong.
pub struct ByteReader<'a> {
    rest: &'a [u8],
    what: &'static str,
}

impl<'a> ByteReader<'a> {
    /// Checks the magic and the checksum of `bytes` and reads the version: the reader stands
    /// after it. `what` names the bytes in errors ("the serialized FMU state"), `kind` what the
    /// magic says they are ("a stiction FMU state").
    pub fn open(
        bytes: &'a [u8],
        magic: &[u8; 8],
        what: &'static str,
        kind: &str,
    ) -> ReadResult<(Self, u32)> {
        let mut r = Self { rest: &[], what };
        if bytes.len() < magic.len() + 12 || &bytes[..magic.len()] != magic {
            return Err(r.bad(&format!("it is not {kind}")));
        }
        let (body, sum) = bytes.split_at(bytes.len() - 8);
        if checksum(body).to_le_bytes() != sum {
            return Err(r.bad("its checksum does not match (truncated or corrupted bytes)"));
        }
        r.rest = &body[magic.len()..];
        let version = r.u32()?;
        Ok((r, version))
    }
    /// The error `what` is wrong with the bytes.
    pub fn bad(&self, what: &str) -> String {
        format!("{} is not valid: {what}", self.what)
    }
    /// Every byte read.
    pub fn end(&self) -> ReadResult<()> {
        match self.rest.is_empty() {
            true => Ok(()),
            false => Err(self.bad("bytes left over after the state")),
        }
    }
    fn take(&mut self, n: usize) -> ReadResult<&[u8]> {
        if n > self.rest.len() {
            return Err(self.bad("it ends too early"));
        }
        let (head, rest) = self.rest.split_at(n);
        self.rest = rest;
        Ok(head)
    }
    fn array<const N: usize>(&mut self) -> ReadResult<[u8; N]> {
        Ok(self.take(N)?.try_into().expect("N bytes taken"))
    }
    fn u8(&mut self) -> ReadResult<u8> {
        Ok(self.take(1)?[0])
    }
    pub fn u32(&mut self) -> ReadResult<u32> {
        Ok(u32::from_le_bytes(self.array()?))
    }
    pub fn u64(&mut self) -> ReadResult<u64> {
        Ok(u64::from_le_bytes(self.array()?))
    }
    fn usize(&mut self) -> ReadResult<usize> {
        usize::try_from(self.u64()?).map_err(|_| self.bad("a count out of range"))
    }
    pub fn f64(&mut self) -> ReadResult<f64> {
        Ok(f64::from_bits(self.u64()?))
    }
    pub fn flag(&mut self) -> ReadResult<bool> {
        match self.u8()? {
            0 => Ok(false),
            1 => Ok(true),
            b => Err(self.bad(&format!("{b} is not a Boolean"))),
        }
    }
    /// A count of items of at least `size` bytes each, no more than the bytes left can hold.
    pub fn count(&mut self, size: usize) -> ReadResult<usize> {
        let n = self.u32()? as usize;
        if n.saturating_mul(size) > self.rest.len() {
            return Err(self.bad("it ends too early"));
        }
        Ok(n)
    }
    pub fn text(&mut self) -> ReadResult<String> {
        let n = self.count(1)?;
        let bytes = self.take(n)?.to_vec();
        String::from_utf8(bytes).map_err(|_| self.bad("a name is not UTF-8"))
    }
    pub fn floats(&mut self) -> ReadResult<Vec<f64>> {
        let n = self.count(8)?;
        (0..n).map(|_| self.f64()).collect()
    }
    pub fn option(&mut self) -> ReadResult<Option<f64>> {
        let (some, v) = (self.flag()?, self.f64()?);
        Ok(some.then_some(v))
    }
    fn element(&mut self) -> ReadResult<SwitchState> {
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
    fn input_change(&mut self) -> ReadResult<InputChange> {
        Ok(InputChange {
            time: self.f64()?,
            input: self.usize()?,
            value: self.f64()?,
        })
    }
    fn parameter_change(&mut self) -> ReadResult<ParameterChange> {
        let (time, after_inputs) = (self.f64()?, self.usize()?);
        let n = self.count(6)?;
        let values = (0..n)
            .map(|_| Ok((self.text()?, self.value(0)?)))
            .collect::<ReadResult<_>>()?;
        Ok(ParameterChange {
            time,
            after_inputs,
            values,
        })
    }
    /// A model-file value (`ByteWriter::value`), nested at most a few levels as tables are.
    fn value(&mut self, depth: usize) -> ReadResult<toml::Value> {
        if depth > 8 {
            return Err(self.bad("values nested too deep"));
        }
        Ok(match self.u8()? {
            0 => toml::Value::Float(self.f64()?),
            1 => toml::Value::Integer(self.u64()? as i64),
            2 => toml::Value::Boolean(self.flag()?),
            3 => {
                let n = self.count(1)?;
                let items = (0..n).map(|_| self.value(depth + 1));
                toml::Value::Array(items.collect::<ReadResult<_>>()?)
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
            tag => return Err(self.bad(&format!("value tag {tag}"))),
        })
    }
    /// A saved run (`ByteWriter::state`).
    pub fn state(&mut self) -> ReadResult<SimState> {
        let x = self.floats()?;
        let n = self.count(5 + MAX_RELATIONS)?;
        let switching = (0..n).map(|_| self.element()).collect::<ReadResult<_>>()?;
        let n = self.count(1)?;
        let relations = (0..n).map(|_| self.flag()).collect::<ReadResult<_>>()?;
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
            .collect::<ReadResult<_>>()?;
        let n = self.count(20)?;
        let parameters = (0..n)
            .map(|_| self.parameter_change())
            .collect::<ReadResult<_>>()?;
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A state with one of everything: two elements, relations, an input, a parameter change
    /// with nested values.
    fn sample() -> SimState {
        let element = |mode: i8, locked: bool| SwitchState {
            pre: Discrete {
                mode,
                start_forward: !locked,
                start_backward: false,
            },
            locked,
            free: false,
            rel: RelationSet([true, false, true, false, false, false, false, true]),
        };
        let mut table = toml::Table::new();
        table.insert("a".into(), toml::Value::Boolean(true));
        SimState {
            inputs: vec![InputChange {
                time: 0.5,
                input: 1,
                value: -2.25,
            }],
            parameters: vec![ParameterChange {
                time: 0.75,
                after_inputs: 1,
                values: vec![
                    ("clutch.fn_max".into(), toml::Value::Float(30.0)),
                    ("J.w".into(), toml::Value::Integer(-3)),
                    ("t.table".into(), toml::Value::Array(vec![table.into()])),
                ],
            }],
            x: vec![1.0, -0.0, f64::MIN_POSITIVE, 1e300],
            disc: DiscreteState {
                switching: vec![element(1, false), element(0, true)],
                relations: vec![true, false],
                inputs: vec![0.25],
            },
            horizon: 1.5,
            cursor: Cursor {
                now: 0.8,
                stop: 2.0,
                next_te: 3,
                grid_k: 80,
                finished: false,
            },
        }
    }

    #[test]
    fn a_state_round_trips_bit_for_bit() {
        let state = sample();
        let bytes = state.to_bytes();
        let back = SimState::from_bytes(&bytes).expect("reads back");
        assert_eq!(back, state);
        assert_eq!(back.x[1].to_bits(), (-0.0f64).to_bits());
        assert_eq!(back.to_bytes(), bytes);
    }

    #[test]
    fn bad_bytes_are_an_error_naming_what_is_wrong() {
        let bytes = sample().to_bytes();
        let message = |b: &[u8]| SimState::from_bytes(b).unwrap_err().to_string();
        assert!(message(&bytes[..bytes.len() - 1]).contains("checksum"));
        assert!(message(b"STICFMUS0000000000000").contains("not a stiction state"));
        let mut flipped = bytes.clone();
        flipped[20] ^= 1;
        assert!(message(&flipped).contains("checksum"));
        // every truncation, re-framed with a valid checksum, fails cleanly
        for n in 12..bytes.len() - 8 {
            let mut w = ByteWriter(bytes[..n].to_vec());
            w.0.truncate(n);
            let framed = w.finish();
            assert!(SimState::from_bytes(&framed).is_err(), "{n} bytes");
        }
    }

    /// The state's bytes, pinned: a change to what `ByteWriter::state` writes fails here, and
    /// is a new `STATE_BYTES_VERSION` (the FMU's format carries it).
    #[test]
    fn state_bytes_are_pinned() {
        let mut w = ByteWriter(Vec::new());
        w.state(&sample());
        let sum = checksum(&w.0);
        assert_eq!(
            (STATE_BYTES_VERSION, w.0.len(), sum),
            (3, 247, 8832830080369188551),
            "the state's bytes changed: bump STATE_BYTES_VERSION (and the FMU's VERSION)"
        );
    }
}
