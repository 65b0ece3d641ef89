//! MSL `Components.InitializeFlange`: the angle and speed of a flange start at the values of
//! input signals at the start time (`phi_start`, `w_start`, each enabled by its `use_…`); the
//! component puts no torque on the flange (`flange.tau = 0`), so afterwards it has no effect
//! on the motion. The start values are fixed ones (`InitEq::signal`), so another fixed start
//! of the same flange is refused by name as over-determined.
//!
//! MSL's third option, `use_a_start` (an initial equation on the acceleration), is refused:
//! here the acceleration at the start follows from the torques on the flange, and no start
//! value of a state can be freed to meet a required one.

use super::{Component, Entry, Ports};
use crate::error::ModelResult;
use crate::model::Params;
use crate::system::{Builder, Out, Rel};

const USE_PHI_START: &str = "use_phi_start true: initial angle is defined by input phi_start";
const USE_W_START: &str = "use_w_start true: initial speed is defined by input w_start";
const USE_A_START: &str = "use_a_start true: initial angular acceleration is defined by input \
     a_start (refused: the acceleration at the start follows from the torques; set it false)";

struct InitializeFlange {
    use_phi_start: bool,
    use_w_start: bool,
    /// Only in the catalogue (which shows every conditional port): a run refuses it.
    use_a_start: bool,
}

impl InitializeFlange {
    fn inputs(&self) -> Vec<&'static str> {
        let flags = [
            (self.use_phi_start, "phi_start"),
            (self.use_w_start, "w_start"),
            (self.use_a_start, "a_start"),
        ];
        flags.iter().filter(|f| f.0).map(|f| f.1).collect()
    }
}

impl Component for InitializeFlange {
    fn ports(&self) -> Ports {
        Ports {
            mech: vec!["flange"],
            signal_in: self.inputs(),
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let nf = b.node("flange")?;
        let rel = Rel::of(&[(nf, 1.0)]);
        if self.use_phi_start {
            let slot = b.signal_in("phi_start")?;
            b.init_angle_from(rel.clone(), slot, "phi_flange");
        }
        if self.use_w_start {
            let slot = b.signal_in("w_start")?;
            b.init_speed_from(rel.clone(), slot, "w_flange");
        }
        b.output("phi_flange", Out::Angle(rel.clone()));
        b.output("w_flange", Out::Speed(rel));
        for port in self.inputs() {
            let slot = b.signal_in(port)?;
            b.output(port, Out::Signal(slot));
        }
        // MSL's Set_flange_tau: the component puts no torque on the flange
        b.flange("flange", nf, Some(Out::Const(0.0)))
    }
}

fn initialize_flange(p: &Params) -> ModelResult<Box<dyn Component>> {
    let use_phi_start = p.boolean(USE_PHI_START, true)?;
    let use_w_start = p.boolean(USE_W_START, true)?;
    let use_a_start = p.boolean(USE_A_START, true)?;
    if use_a_start && !p.in_catalogue() {
        return Err(p.error(
            "use_a_start",
            "an initial angular acceleration cannot be required: the acceleration at the start \
             follows from the torques on the flange (an Inertia's J·a), with no start value left \
             free to meet it; set use_a_start = false (and give the torques that produce it)",
        ));
    }
    Ok(Box::new(InitializeFlange {
        use_phi_start,
        use_w_start,
        use_a_start,
    }))
}

pub const REGISTRY: &[Entry] = &[Entry::new(
    "InitializeFlange",
    "Modelica.Mechanics.Rotational.Components.InitializeFlange",
    "Initializes a flange with pre-defined angle, speed and angular acceleration (usually, this is reference data from a control bus)",
    initialize_flange,
)];
