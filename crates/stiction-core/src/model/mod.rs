//! What the user describes: the model file (TOML), its components, their parameters and the
//! connections, read and validated into plain data before anything is assembled.

mod decl;
mod expr;
mod names;
mod params;
mod spec;

pub use decl::{parse_decl, ParamInfo, ParamKind};
pub use expr::{BinOp, DerivedSpec, Expr, CONSTANTS};
pub use names::{check_prefixes, near, split_last};
pub use params::{overriding, InitValue, Params};
pub use spec::{ComponentSpec, Experiment, InputSpec, ModelSpec, PortRef};
