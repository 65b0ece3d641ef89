//! What a component says about each parameter where it reads it: the declaration string
//! `"name [unit] description"` (as Modelica writes `parameter SI.Torque tau "description"`),
//! and the catalogue entry recorded from it when a constructor runs in catalogue mode.

/// The kind of value a parameter holds.
#[derive(Debug, Clone, PartialEq)]
pub enum ParamKind {
    Real,
    Boolean,
    /// A start value: a number (fixed) or `{ start = …, fixed = … }`.
    Start,
    /// The start value of a Boolean discrete state.
    BooleanStart,
    /// A table with this many columns, rows `[x, y…]`.
    Table(usize),
    /// A list of numbers (a CombiTimeTable's `columns`, `offset`); a bare number is a list of one.
    Vector,
    String,
    /// One of these names.
    Choice(Vec<String>),
    /// A table of named values, e.g. a friction element's `wear = { model = "energy", … }`;
    /// not given (its default, an empty table) means none.
    Record,
}

impl ParamKind {
    /// Short name of the kind, as the reference and Python show it.
    pub fn label(&self) -> String {
        match self {
            ParamKind::Real => "Real".into(),
            ParamKind::Boolean => "Boolean".into(),
            ParamKind::Start => "start value".into(),
            ParamKind::BooleanStart => "Boolean start value".into(),
            ParamKind::Table(n) => format!("table [:, {n}]"),
            ParamKind::Vector => "vector".into(),
            ParamKind::String => "String".into(),
            ParamKind::Choice(_) => "choice".into(),
            ParamKind::Record => "record".into(),
        }
    }

    /// Whether the value is a number (and so must state a unit).
    pub fn is_numeric(&self) -> bool {
        matches!(
            self,
            ParamKind::Real | ParamKind::Start | ParamKind::Table(_) | ParamKind::Vector
        )
    }
}

/// One parameter as the catalogue lists it.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamInfo {
    pub name: String,
    pub kind: ParamKind,
    /// MSL's default; `None` when MSL gives none (the user must set it) or none applies
    /// (TimeTable's `file`).
    pub default: Option<toml::Value>,
    pub required: bool,
    /// Modelica unit string (`"N.m"`, `"rad/s"`, `"1"`); for tables one per column.
    pub unit: String,
    pub description: String,
    /// The valid range as a condition on the value (`">= 0"`, `"> 0"`, `"(0, 100]"`).
    pub range: Option<String>,
}

/// Real parameters a running simulation cannot take anew, each with the reason: they fix a
/// position (a gear's ratio ties the angles, a ground's angle, a prescribed speed) or the
/// instants of the time events, which the run has planned (a TimeTable's `table` holds its
/// abscissae).
const FIXED: &[(&str, &str)] = &[
    (
        "ratio",
        "the gear's position constraint holds from the start",
    ),
    (
        "phi0",
        "the ground's angle is a position the run has reached",
    ),
    (
        "s0",
        "the ground's position is a position the run has reached",
    ),
    ("L", "a mass's length places its flanges"),
    (
        "radius",
        "the wheel's position constraint holds from the start",
    ),
    (
        "w_fixed",
        "the prescribed speed is a state the run has reached",
    ),
    ("startTime", "it places a time event"),
    ("period", "it places time events"),
    ("width", "it places time events"),
    ("nperiod", "it places time events"),
    ("duration", "it places a time event"),
    ("shiftTime", "it places time events"),
    ("timeScale", "it places time events"),
    ("table", "its abscissae place time events"),
];

impl ParamInfo {
    /// Why the parameter cannot change in a running simulation, or None if it can (it is
    /// *tunable*): Booleans, strings and choices change the structure, start values act
    /// only at initialization, and some Real parameters fix positions or time events.
    pub fn fixed_because(&self) -> Option<&'static str> {
        match self.kind {
            ParamKind::Real | ParamKind::Table(_) => (FIXED.iter())
                .find(|(name, _)| *name == self.name)
                .map(|(_, why)| *why),
            ParamKind::Start | ParamKind::BooleanStart => {
                Some("a start value acts at initialization only")
            }
            _ => Some("it decides the structure of the compiled model"),
        }
    }

    /// Whether a running simulation (and an FMU in step mode) can take a new value.
    pub fn tunable(&self) -> bool {
        self.fixed_because().is_none()
    }
}

/// Splits `"name [unit] description"` into its three parts (unit and description may be empty).
pub fn parse_decl(decl: &str) -> (&str, &str, &str) {
    let decl = decl.trim();
    let (name, rest) = decl.split_once(char::is_whitespace).unwrap_or((decl, ""));
    let rest = rest.trim_start();
    match rest.strip_prefix('[').and_then(|r| r.split_once(']')) {
        Some((unit, doc)) => (name, unit.trim(), doc.trim()),
        None => (name, "", rest.trim()),
    }
}

/// The name of a declaration alone, `parse_decl(decl).0` without scanning the rest (a compile
/// reads thousands of declarations and needs only their names).
pub fn decl_name(decl: &str) -> &str {
    let decl = decl.trim_start();
    decl.split(char::is_whitespace).next().unwrap_or(decl)
}

#[cfg(test)]
mod tests {
    use super::{decl_name, parse_decl};

    #[test]
    fn a_declarations_name_alone_is_the_name_parse_decl_gives() {
        for decl in [
            "J [kg.m2] Moment of inertia",
            "  useSupport Enable the support",
            "peak",
            " peak ",
            "mu_pos [rad/s, 1] mu at w, mu_pos[1,2]",
            "tau\tTorque",
            "",
        ] {
            assert_eq!(decl_name(decl), parse_decl(decl).0, "{decl:?}");
        }
    }

    #[test]
    fn declarations_split_into_name_unit_and_description() {
        assert_eq!(
            parse_decl("J [kg.m2] Moment of inertia"),
            ("J", "kg.m2", "Moment of inertia")
        );
        assert_eq!(
            parse_decl("useSupport Enable the support"),
            ("useSupport", "", "Enable the support")
        );
        assert_eq!(parse_decl("peak"), ("peak", "", ""));
        assert_eq!(
            parse_decl("mu_pos [rad/s, 1] mu at w, mu_pos[1,2]"),
            ("mu_pos", "rad/s, 1", "mu at w, mu_pos[1,2]")
        );
    }
}
