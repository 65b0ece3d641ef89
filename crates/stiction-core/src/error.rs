//! Errors of the core: every model error names the component and the parameter or port at fault;
//! every simulation error says what failed, when, and which elements were involved. Each kind is
//! its own variant so callers (Python, FMI, the CLI) can map it without reading messages.

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
    /// The model file itself (syntax, experiment settings, format version).
    #[error("{0}")]
    File(String),
}

/// A failure while simulating a valid model.
#[derive(Debug, Clone, Error, PartialEq)]
pub enum SimError {
    #[error(transparent)]
    Model(#[from] ModelError),
    /// The mode's linear system has no unique solution.
    #[error("at t = {time}: the accelerations are not determined (singular system){detail}")]
    SingularMode { time: f64, detail: String },
    /// The event iteration found no consistent discrete state.
    #[error("at t = {time}: {message} (elements: {})", elements.join(", "))]
    EventIteration {
        time: f64,
        message: String,
        elements: Vec<String>,
    },
    /// One element changes its mode again and again within a vanishing time window.
    #[error("at t = {time}: '{element}' changed its mode {changes} times within {window:e} s (last: {cause}): the model chatters")]
    Chattering {
        time: f64,
        element: String,
        changes: usize,
        window: f64,
        cause: String,
    },
    /// A limit the user set (`max_events`, `max_steps`, `timeout`) was reached.
    #[error("at t = {time}: the run reached its limit {limit}")]
    Limit { time: f64, limit: String },
    /// More integration steps than any sensible run needs.
    #[error(
        "at t = {time}: more than {limit} integration steps: the model is too stiff or chatters"
    )]
    StepLimit { time: f64, limit: usize },
    /// The state became infinite or NaN.
    #[error(
        "at t = {time}: the state became infinite or NaN (overflow, or a mode without a solution)"
    )]
    NonFiniteState { time: f64 },
    /// A friction characteristic went below 0 during the run (a table extrapolated past its
    /// last row): the friction would drive the motion and deliver energy.
    #[error("at t = {time}: {message}")]
    NegativeFriction {
        time: f64,
        element: String,
        message: String,
    },
    /// A worn pad reached its `thickness_min` (the `wear` record): the run stops there.
    #[error("at t = {time}: '{element}': the pad wore down to thickness_min = {thickness_min} m (worn volume {volume} m3)")]
    WearLimit {
        time: f64,
        element: String,
        thickness_min: f64,
        volume: f64,
    },
    /// The ODE integrator itself failed (step size too small, nonlinear solver failures, …).
    #[error("at t = {time}: integrator: {message}")]
    Integrator { time: f64, message: String },
    /// The run was cancelled (`Simulation::cancel`, Ctrl-C).
    #[error("at t = {time}: cancelled")]
    Cancelled { time: f64 },
    /// A request the running simulation cannot honour (an unknown input or variable, a time
    /// before the current one or past StopTime).
    #[error("{0}")]
    Usage(String),
}

impl SimError {
    /// A short machine-readable name of the kind (the Python exception class is chosen by it).
    pub fn kind(&self) -> &'static str {
        match self {
            SimError::Model(_) => "ModelError",
            SimError::SingularMode { .. } => "SingularSystemError",
            SimError::EventIteration { .. } => "EventIterationError",
            SimError::Chattering { .. } => "ChatteringError",
            SimError::StepLimit { .. } => "StepLimitError",
            SimError::Limit { .. } => "LimitExceededError",
            SimError::NonFiniteState { .. } => "NonFiniteStateError",
            SimError::NegativeFriction { .. } => "NegativeFrictionError",
            SimError::WearLimit { .. } => "WearLimitError",
            SimError::Integrator { .. } => "IntegratorError",
            SimError::Cancelled { .. } => "SimulationCancelled",
            SimError::Usage(_) => "UsageError",
        }
    }
}

pub type ModelResult<T> = Result<T, ModelError>;
