//! The signal graph's evaluation order and stages (`signals::Stage`), and the check of what a
//! sensor's signal may drive: a signal known only after the linear solve (an acceleration, a cut
//! torque, a power) must not reach an input the solve depends on, and no sensor signal may
//! prescribe a motion (the motion it measures would be the one it sets).

use crate::error::{ModelError, ModelResult};
use crate::signals::{BlockElem, SignalGraph, Stage};
use crate::system::Builder;

/// Orders the blocks, splits them into stages and checks every consumer of a sensor's signal.
pub(super) fn stage(b: &mut Builder) -> ModelResult<()> {
    order(&mut b.sys.signals)?;
    let graph = &mut b.sys.signals;
    // per slot: its stage and the sensor behind it (`component.port`), if any
    let mut stage = vec![Stage::Time; graph.slots];
    let mut origin: Vec<Option<String>> = vec![None; graph.slots];
    for s in graph.state.sensors.iter().chain(&graph.solved.sensors) {
        stage[s.slot] = s.measure.stage();
        origin[s.slot] = Some(format!("{}.{}", s.owner, s.port));
    }
    if graph.state.sensors.is_empty() && graph.solved.sensors.is_empty() {
        return Ok(()); // every block depends on time and model inputs alone
    }
    let mut time = Vec::new();
    for block in std::mem::take(&mut graph.blocks) {
        let from = (block.inputs.iter()).max_by_key(|&&s| stage[s]).copied();
        if let Some(from) = from {
            stage[block.output] = stage[from];
            origin[block.output] = origin[from].clone();
        }
        match stage[block.output] {
            Stage::Time => time.push(block),
            Stage::State => graph.state.blocks.push(block),
            Stage::Solved => graph.solved.blocks.push(block),
        }
    }
    graph.blocks = time;
    check_consumers(b, &stage, &origin)
}

/// No input of a mechanical component (or of the thermal network) reads a signal of
/// `Stage::Solved`; no prescribed motion reads a sensor's signal at all.
fn check_consumers(b: &Builder, stage: &[Stage], origin: &[Option<String>]) -> ModelResult<()> {
    for (comp, port, slot) in &b.signal_reads {
        if b.block_owners.contains(comp) || stage[*slot] != Stage::Solved {
            continue;
        }
        let sensor = origin[*slot].as_deref().unwrap_or("a sensor");
        return Err(ModelError::Component {
            component: b.names[*comp].clone(),
            message: format!(
                "input '{port}' is driven by {sensor} (through the blocks between them): an \
                 acceleration, cut torque or power is known only after the solve that this \
                 input's torque takes part in — an algebraic loop, which stiction does not \
                 solve; measure an angle or a speed instead (AngleSensor, SpeedSensor, \
                 RelSpeedSensor …)"
            ),
        });
    }
    for c in &b.sys.constraints {
        let Some(p) = &c.prescribed else { continue };
        // held values are set before the sensors read the shafts; an acceleration is read
        // after the angle and speed sensors (a filter may follow a measured speed)
        let (held, accel) = p.slots();
        let late = |s: &usize, after: Stage| stage[*s] > after;
        let loop_slot = (held.iter().flatten().find(|s| late(s, Stage::Time)))
            .or_else(|| accel.iter().find(|s| late(s, Stage::State)));
        if let Some(&slot) = loop_slot {
            let sensor = origin[slot].as_deref().unwrap_or("a sensor");
            return Err(ModelError::Component {
                component: c.owner.clone(),
                message: format!(
                    "its prescribed motion is driven by {sensor}: a motion set from a \
                     measured motion is an algebraic loop, which stiction does not solve"
                ),
            });
        }
    }
    Ok(())
}

/// Orders blocks so that every block comes after the blocks it reads; a loop is an error.
fn order(graph: &mut SignalGraph) -> ModelResult<()> {
    let mut pending: Vec<BlockElem> = std::mem::take(&mut graph.blocks);
    // A slot no block writes (a model input, a sensor's output) is ready from the start.
    let mut ready = vec![true; graph.slots];
    for block in &pending {
        ready[block.output] = false;
    }
    let mut ordered = Vec::with_capacity(pending.len());
    while !pending.is_empty() {
        let before = pending.len();
        let mut k = 0;
        while k < pending.len() {
            if pending[k].inputs.iter().all(|&s| ready[s]) {
                let block = pending.remove(k);
                ready[block.output] = true;
                ordered.push(block);
            } else {
                k += 1;
            }
        }
        if pending.len() == before {
            return Err(ModelError::Component {
                component: pending[0].owner.clone(),
                message: "its inputs form an algebraic loop of signal blocks".into(),
            });
        }
    }
    graph.blocks = ordered;
    Ok(())
}
