//! Errors of the core: every model error names the component and the parameter or port at fault.

use thiserror::Error;

/// A problem with the model a user described (caught before or while assembling it).
#[derive(Debug, Clone, Error, PartialEq)]
pub enum ModelError {
    /// A parameter of a component is missing, of the wrong kind or out of range.
    #[error("component '{component}' ({type_name}): parameter '{parameter}': {message}")]
    Parameter {
        component: String,
        type_name: String,
        parameter: String,
        message: String,
    },
    /// A connection names a port that does not exist or cannot be connected that way.
    #[error("connection {connection}: {message}")]
    Connection { connection: String, message: String },
    /// A component-level problem that is not tied to one parameter (unknown type, port left open …).
    #[error("component '{component}': {message}")]
    Component { component: String, message: String },
    /// The model file itself (syntax, experiment settings).
    #[error("{0}")]
    File(String),
}

/// A failure while simulating a valid model (singular system, event iteration not converging …).
#[derive(Debug, Clone, Error, PartialEq)]
pub enum SimError {
    #[error(transparent)]
    Model(#[from] ModelError),
    #[error("at t = {time}: {message}")]
    Numerical { time: f64, message: String },
}

pub type ModelResult<T> = Result<T, ModelError>;
