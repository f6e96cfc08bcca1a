//! The planner registry: one [`PlannerEntry`] per planner, declared next to its code, with its
//! name, a one-line description citing its paper, its parameters (name, default, doc) and a build
//! function. The binary lists entries (`mrpp planners`), turns `-p key=value` into [`Params`]
//! (unknown keys are refused with the list of valid ones) and builds planners from them; the
//! property tests iterate the registry, so a planner is tested by being registered.

use std::collections::BTreeMap;
use std::str::FromStr;

use crate::contract::{Planner, Problem};
use crate::error::{Error, Result};

/// One planner parameter: its `-p` key, default value (as text) and a one-line doc.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Param {
    pub name: &'static str,
    pub default: &'static str,
    pub doc: &'static str,
}

/// A registered planner for problems of type `P`.
pub struct PlannerEntry<P: Problem> {
    /// Unique across all families.
    pub name: &'static str,
    /// One line, with its paper.
    pub about: &'static str,
    pub params: &'static [Param],
    /// Builds the planner; parameters are already checked against [`PlannerEntry::params`] and
    /// filled with defaults, so the function only parses and range-checks them.
    pub build: fn(&Params) -> Result<Box<dyn Planner<P>>>,
}

impl<P: Problem> PlannerEntry<P> {
    /// Checks `given` against the declared parameters, fills in defaults and builds the planner.
    pub fn instantiate(&self, given: &[(String, String)]) -> Result<Box<dyn Planner<P>>> {
        (self.build)(&Params::resolve(self.name, self.params, given)?)
    }
}

/// The finder of a family's registry: the entry named `name`, if any.
pub fn find<'a, P: Problem>(
    entries: &'a [PlannerEntry<P>],
    name: &str,
) -> Option<&'a PlannerEntry<P>> {
    entries.iter().find(|e| e.name == name)
}

/// The parameter values of one planner run: every declared key, with the user's value or the
/// default. Keys are ordered, so printing them is deterministic.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Params {
    planner: String,
    values: BTreeMap<String, String>,
    /// Keys the user set (the others hold defaults).
    given: Vec<String>,
}

impl Params {
    /// Validates `given` (`key=value` pairs in order; a later value wins) against `declared`.
    ///
    /// # Errors
    /// [`Error::Param`] for an unknown key, naming the valid ones.
    pub fn resolve(planner: &str, declared: &[Param], given: &[(String, String)]) -> Result<Self> {
        let mut values: BTreeMap<String, String> = declared
            .iter()
            .map(|p| (p.name.to_string(), p.default.to_string()))
            .collect();
        let mut set = Vec::new();
        for (k, v) in given {
            if !values.contains_key(k) {
                let valid: Vec<&str> = declared.iter().map(|p| p.name).collect();
                return Err(Error::Param(format!(
                    "planner `{planner}` has no parameter `{k}` (valid: {})",
                    if valid.is_empty() {
                        "none".to_string()
                    } else {
                        valid.join(", ")
                    }
                )));
            }
            values.insert(k.clone(), v.clone());
            if !set.contains(k) {
                set.push(k.clone());
            }
        }
        Ok(Params {
            planner: planner.to_string(),
            values,
            given: set,
        })
    }

    /// The raw text of `key` (declared keys always have one).
    pub fn raw(&self, key: &str) -> &str {
        self.values.get(key).map(String::as_str).unwrap_or("")
    }

    /// `key` parsed as `T`.
    ///
    /// # Errors
    /// [`Error::Param`] naming the planner, key and value when it does not parse.
    pub fn get<T: FromStr>(&self, key: &str) -> Result<T> {
        let raw = self.raw(key);
        raw.parse().map_err(|_| {
            Error::Param(format!(
                "planner `{}`: parameter {key}={raw} is not {}",
                self.planner,
                what_is::<T>()
            ))
        })
    }

    /// `key` parsed as `T` and checked to lie in `range`.
    pub fn get_in<T>(&self, key: &str, range: std::ops::RangeInclusive<T>) -> Result<T>
    where
        T: FromStr + PartialOrd + std::fmt::Display,
    {
        let v: T = self.get(key)?;
        if !range.contains(&v) {
            return Err(Error::Param(format!(
                "planner `{}`: parameter {key} must be between {} and {}, got {v}",
                self.planner,
                range.start(),
                range.end()
            )));
        }
        Ok(v)
    }

    /// `key` as one of `choices` (its index).
    pub fn choice(&self, key: &str, choices: &[&str]) -> Result<usize> {
        let raw = self.raw(key);
        choices.iter().position(|c| *c == raw).ok_or_else(|| {
            Error::Param(format!(
                "planner `{}`: parameter {key}={raw} is not one of {}",
                self.planner,
                choices.join(", ")
            ))
        })
    }

    /// Every key with its value, in key order (what an output records).
    pub fn iter(&self) -> impl Iterator<Item = (&str, &str)> {
        self.values.iter().map(|(k, v)| (k.as_str(), v.as_str()))
    }

    /// Whether the user set `key` (as opposed to its default).
    pub fn is_given(&self, key: &str) -> bool {
        self.given.iter().any(|k| k == key)
    }
}

/// What a value of type `T` is, in words a user reads (not Rust's type names).
fn what_is<T>() -> &'static str {
    match std::any::type_name::<T>() {
        "u8" | "u16" | "u32" | "u64" | "u128" | "usize" => "a whole number from 0",
        "i8" | "i16" | "i32" | "i64" | "i128" | "isize" => "a whole number",
        "f32" | "f64" => "a number",
        "bool" => "true or false",
        _ => "a valid value",
    }
}

/// Parses one `key=value` argument.
///
/// # Errors
/// [`Error::Param`] when there is no `=` or the key is empty.
pub fn parse_key_value(arg: &str) -> Result<(String, String)> {
    match arg.split_once('=') {
        Some((k, v)) if !k.trim().is_empty() => Ok((k.trim().to_string(), v.trim().to_string())),
        _ => Err(Error::Param(format!(
            "`{arg}` is not key=value (e.g. -p window=8)"
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DECLARED: &[Param] = &[
        Param {
            name: "window",
            default: "8",
            doc: "w",
        },
        Param {
            name: "variant",
            default: "a",
            doc: "v",
        },
    ];

    #[test]
    fn defaults_values_and_unknown_keys() {
        let p = Params::resolve("x", DECLARED, &[("window".into(), "3".into())]).unwrap();
        assert_eq!(p.get::<u32>("window").unwrap(), 3);
        assert_eq!(p.raw("variant"), "a");
        assert!(p.is_given("window") && !p.is_given("variant"));
        assert_eq!(p.choice("variant", &["b", "a"]).unwrap(), 1);
        let e = Params::resolve("x", DECLARED, &[("widow".into(), "3".into())])
            .unwrap_err()
            .to_string();
        assert!(e.contains("widow") && e.contains("window, variant"), "{e}");
        let p = Params::resolve("x", DECLARED, &[("window".into(), "0".into())]).unwrap();
        let e = p.get_in::<u32>("window", 1..=9).unwrap_err().to_string();
        assert!(e.contains("between 1 and 9"), "{e}");
        assert!(parse_key_value("a=b").is_ok() && parse_key_value("ab").is_err());
    }
}
