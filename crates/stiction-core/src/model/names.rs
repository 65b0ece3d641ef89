//! Hierarchical names: a component's name is a dotted path of identifiers (`front.clutch`, as
//! Modelica tools flatten a user's class), its ports and parameters one more segment
//! (`front.clutch.flange_a`, `front.clutch.peak`), its variables one or more
//! (`front.clutch.flange_a.tau`). Names are resolved when a model is read or compiled, never
//! while it runs.

use crate::error::{ModelError, ModelResult};

/// An identifier: a letter or `_`, then letters, digits and `_`.
pub(crate) fn is_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// A component's name: identifiers joined by dots (`J1`, `front.clutch`).
pub(crate) fn is_component_name(name: &str) -> bool {
    name.split('.').all(is_identifier)
}

/// `component.last` split at the last dot (a port or a parameter is the last segment; a
/// table cell such as `mu_pos[1,2]` has no dot); None without a dot or with an empty side.
pub fn split_last(name: &str) -> Option<(&str, &str)> {
    name.rsplit_once('.')
        .filter(|(head, last)| !head.is_empty() && !last.is_empty())
}

/// For an unknown `name`, the variables of its nearest known prefix: the longest dotted
/// prefix of `name` (itself included) that starts some of `names` (for `front.clutch.w_rlx`,
/// `front.clutch` and its variables). None when no prefix matches.
pub fn near<'a>(name: &'a str, names: &'a [String]) -> Option<(&'a str, Vec<&'a str>)> {
    let mut prefix = Some(name);
    while let Some(p) = prefix {
        prefix = p.rsplit_once('.').map(|(head, _)| head);
        let prefix = p;
        let found: Vec<&str> = (names.iter())
            .filter(|n| n.len() > prefix.len() && n.starts_with(prefix))
            .filter(|n| n.as_bytes()[prefix.len()] == b'.')
            .map(String::as_str)
            .take(12)
            .collect();
        if !found.is_empty() {
            return Some((prefix, found));
        }
    }
    None
}

/// Refuses a component name that is a dotted prefix of another's (`front` and
/// `front.clutch`): `front.clutch.w` would name a variable of both. Checks neighbours in sorted
/// order: `.` sorts before every identifier character, so a name's extensions follow it.
pub fn check_prefixes<'a>(names: impl IntoIterator<Item = &'a str>) -> ModelResult<()> {
    let mut sorted: Vec<&str> = names.into_iter().collect();
    sorted.sort_unstable();
    for pair in sorted.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        if b.len() > a.len() && b.starts_with(a) && b.as_bytes()[a.len()] == b'.' {
            return Err(ModelError::Component {
                component: a.to_string(),
                message: format!(
                    "the name is the start of component '{b}': their variables would be ambiguous ('{b}.…' names either); rename one"
                ),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn component_names_are_dotted_identifiers() {
        for ok in ["J1", "front.clutch", "_a.b2.c"] {
            assert!(is_component_name(ok), "{ok}");
        }
        for bad in [
            "",
            "front.",
            ".clutch",
            "front..clutch",
            "1a",
            "a.1b",
            "a b",
            "a-b",
        ] {
            assert!(!is_component_name(bad), "{bad}");
        }
    }

    #[test]
    fn a_parameter_is_the_last_segment() {
        assert_eq!(
            split_last("front.clutch.peak"),
            Some(("front.clutch", "peak"))
        );
        assert_eq!(split_last("J1.J"), Some(("J1", "J")));
        assert_eq!(split_last("a.b.mu_pos[1,2]"), Some(("a.b", "mu_pos[1,2]")));
        assert_eq!(split_last("StopTime"), None);
        assert_eq!(split_last("a."), None);
    }

    #[test]
    fn a_port_is_the_last_segment_of_its_reference() {
        let p = crate::model::PortRef::parse("front.clutch.flange_a").unwrap();
        assert_eq!(
            (p.component.as_str(), p.port.as_str()),
            ("front.clutch", "flange_a")
        );
        assert_eq!(p.to_string(), "front.clutch.flange_a");
        let p = crate::model::PortRef::parse("J1.flange_b").unwrap();
        assert_eq!((p.component.as_str(), p.port.as_str()), ("J1", "flange_b"));
        for bad in ["J1", "front.clutch.", ".flange_a"] {
            let e = crate::model::PortRef::parse(bad).unwrap_err().to_string();
            assert!(e.contains(bad) && e.contains("'component.port'"), "{e}");
        }
    }

    #[test]
    fn a_component_name_that_starts_another_is_refused_naming_both() {
        assert!(check_prefixes(["front.clutch", "front2", "front_a.b"]).is_ok());
        let err = check_prefixes(["rear", "front", "front0", "front.clutch"]).unwrap_err();
        let text = err.to_string();
        assert!(
            text.contains("'front'") || text.contains("front:"),
            "{text}"
        );
        assert!(text.contains("front.clutch"), "{text}");
    }

    #[test]
    fn near_names_come_from_the_longest_known_prefix() {
        let names: Vec<String> = [
            "front.clutch.w_rel",
            "front.clutch.flange_a.tau",
            "front.J.w",
        ]
        .map(String::from)
        .to_vec();
        let (prefix, found) = near("front.clutch.w_rlx", &names).unwrap();
        assert_eq!(prefix, "front.clutch");
        assert_eq!(found, ["front.clutch.w_rel", "front.clutch.flange_a.tau"]);
        assert_eq!(near("rear.w", &names), None);
        assert_eq!(near("front", &names).unwrap().1.len(), 3);
    }
}
