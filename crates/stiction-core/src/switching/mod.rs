//! The switching elements: everything with stick/slip or quadrant logic, as the engine sees it
//! through one trait (`element`) — MSL's `PartialFriction` rules (`logic`), relations with the event hysteresis (`relation`),
//! the friction element and the LossyGear with their discrete states. Constructors live in
//! `components`; the event iteration and crossings that drive these rules live in `engine`.

pub mod element;
pub mod fade;
pub mod friction;
pub mod logic;
pub mod lossy_gear;
pub mod relation;
pub mod stop;
