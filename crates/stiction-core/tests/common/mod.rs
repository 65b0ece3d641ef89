//! What several test files share.

pub const FLYWHEEL: &str = include_str!("../../../../examples/braked_flywheel.toml");

/// The braked flywheel with its press ramp replaced by a model input.
pub fn flywheel_with_input() -> String {
    FLYWHEEL
        .replace("  [\"press.y\", \"brake.f_normalized\"],\n", "")
        .replace(
            "press = { type = \"Ramp\", height = 1.0, duration = 0.2, startTime = 0.5 }\n",
            "",
        )
        .replace(
            "name = \"braked_flywheel\"",
            "name = \"braked_flywheel\"\ninputs = [\"brake.f_normalized\"]",
        )
}
