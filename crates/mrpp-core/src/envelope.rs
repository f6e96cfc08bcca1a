//! The one plan file of every family: a versioned JSON envelope.
//!
//! ```json
//! {
//!   "format": "mrpp-plan/1",
//!   "family": "grid",
//!   "world": {"kind": "grid-map", "file": "room.map"},
//!   "planner": "whca",
//!   "params": {"window": "8"},
//!   "seed": 0,
//!   "solved": true,
//!   "status": "solved",
//!   "rules": {"goal": "stay", "following": true},
//!   "metrics": {"sum_of_costs": 5, "makespan": 3, "sum_of_moves": 4},
//!   "runtime_ms": 0.4,
//!   "agents": [
//!     {"start": [1, 0], "goal": [2, 0], "path": [[1, 0], [0, 0], [2, 0]]}
//!   ]
//! }
//! ```
//!
//! Path elements fit the family: `[x, y]` cells on grids (x = column, y = row, from the top-left),
//! node ids on trees and roadmaps, `[x, y]` floats in the continuous plane. The index in `path` is
//! the time step and `path[0]` the start; an unsolved run keeps starts and goals (so the file still
//! describes the instance) with empty paths and empty metrics, and `status` says why
//! (`time_limit`, `gave_up`). Keys this version does not know are kept in
//! [`Envelope::extra`] (a family's extras, e.g. a GP program; the keys of older files such as
//! `map_file` and `goal_semantics`), so files written before the envelope still read.
//!
//! [`Envelope::to_json`] writes one agent per line and wraps long paths, so a person can read the
//! file and diffs stay local; everything goes through serde_json, so the text is valid JSON that
//! [`Envelope::parse`] reads back to the same value.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

use crate::error::{Error, Result};

/// The format tag this version writes.
pub const FORMAT: &str = "mrpp-plan/1";

/// Path elements per line in [`Envelope::to_json`].
pub const ELEMENTS_PER_LINE: usize = 16;

/// Which world file a plan was made on.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct World {
    /// The kind of file, e.g. `grid-map`, `tree-instance`.
    pub kind: String,
    /// The file as the planner was given it (its name; informative only).
    pub file: String,
}

/// One agent: its task and its path (empty when unsolved).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(bound(serialize = "E: Serialize", deserialize = "E: DeserializeOwned"))]
pub struct AgentPath<E> {
    pub start: E,
    pub goal: E,
    #[serde(default)]
    pub path: Vec<E>,
}

/// The plan file of any family, generic over its path element `E`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(bound(serialize = "E: Serialize", deserialize = "E: DeserializeOwned"))]
pub struct Envelope<E> {
    /// [`FORMAT`]; empty in files written before the envelope.
    #[serde(default)]
    pub format: String,
    /// The family (`grid`, `trees`, ...); empty in older files.
    #[serde(default)]
    pub family: String,
    #[serde(default)]
    pub world: World,
    #[serde(default)]
    pub planner: String,
    /// Every planner parameter with the value the run used.
    #[serde(default)]
    pub params: BTreeMap<String, String>,
    #[serde(default)]
    pub seed: u64,
    pub solved: bool,
    /// `solved`, `time_limit` or `gave_up` (empty in older files).
    #[serde(default)]
    pub status: String,
    /// The family's rules (MAPF: goal semantics and following); `null` when not recorded.
    #[serde(default)]
    pub rules: Value,
    /// The validator's metrics of a solved plan (empty when unsolved or not reported).
    #[serde(default, deserialize_with = "null_as_empty")]
    pub metrics: Map<String, Value>,
    /// Wall time of the planner (machine-dependent).
    #[serde(default)]
    pub runtime_ms: f64,
    pub agents: Vec<AgentPath<E>>,
    /// Every other key: a family's extras, or the keys of older files.
    #[serde(flatten)]
    pub extra: Map<String, Value>,
}

fn null_as_empty<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Map<String, Value>, D::Error> {
    Ok(Option::<Map<String, Value>>::deserialize(d)?.unwrap_or_default())
}

impl<E: Serialize + DeserializeOwned> Envelope<E> {
    /// Reads an envelope; malformed JSON or a wrong shape becomes [`Error::Parse`] with its
    /// (1-based) line and the key path of the value at fault (`agents[3].path[12]: invalid
    /// type: string "a", expected i64`), not serde's column. A `format` other than [`FORMAT`]
    /// (and not empty) is refused.
    pub fn parse(text: &str, path: &Path) -> Result<Self> {
        let de = &mut serde_json::Deserializer::from_str(text);
        let env: Self = serde_path_to_error::deserialize(de).map_err(|e| {
            let at = e.path().to_string();
            let inner = e.into_inner();
            let line = inner.line().max(1);
            // serde_json appends " at line L column C"; the line is in the error's place.
            let msg = inner.to_string();
            let msg = msg
                .rsplit_once(" at line ")
                .map_or(msg.as_str(), |(m, _)| m)
                .to_string();
            let msg = if at.is_empty() || at == "." {
                msg
            } else {
                format!("`{at}`: {msg}")
            };
            Error::parse(path, line, msg)
        })?;
        if !env.format.is_empty() && env.format != FORMAT {
            return Err(Error::invalid(
                path,
                format!(
                    "plan format `{}` is not one this mrpp reads ({FORMAT})",
                    env.format
                ),
            ));
        }
        Ok(env)
    }

    /// An error naming `path` unless the file holds a plan (`solved: true`).
    pub fn require_solved(&self, path: &Path) -> Result<()> {
        if self.solved {
            Ok(())
        } else {
            Err(Error::invalid(
                path,
                "the file says solved=false: it holds no plan (nothing to check or draw)",
            ))
        }
    }

    /// The metrics the file claims that differ from `actual` ([`disputed`]).
    pub fn disputed_metrics(&self, actual: &Value) -> Vec<(String, Value, Value)> {
        disputed(&self.metrics, actual)
    }

    /// JSON text: header keys one per line, one agent per line, paths wrapped every
    /// [`ELEMENTS_PER_LINE`] elements; extra keys after the header, in their order.
    pub fn to_json(&self) -> String {
        let mut s = String::from("{\n");
        let _ = writeln!(s, "  \"format\": {},", js(&FORMAT));
        let _ = writeln!(s, "  \"family\": {},", js(&self.family));
        let _ = writeln!(s, "  \"world\": {},", js(&self.world));
        let _ = writeln!(s, "  \"planner\": {},", js(&self.planner));
        let _ = writeln!(s, "  \"params\": {},", js(&self.params));
        let _ = writeln!(s, "  \"seed\": {},", self.seed);
        let _ = writeln!(s, "  \"solved\": {},", self.solved);
        let _ = writeln!(s, "  \"status\": {},", js(&self.status));
        let _ = writeln!(s, "  \"rules\": {},", js(&self.rules));
        let _ = writeln!(s, "  \"metrics\": {},", js(&self.metrics));
        let runtime = if self.runtime_ms.is_finite() {
            self.runtime_ms
        } else {
            0.0
        };
        let _ = writeln!(s, "  \"runtime_ms\": {},", js(&runtime));
        for (k, v) in &self.extra {
            let _ = writeln!(s, "  {}: {},", js(k), js(v));
        }
        if self.agents.is_empty() {
            s.push_str("  \"agents\": []\n}\n");
            return s;
        }
        s.push_str("  \"agents\": [\n");
        for (i, a) in self.agents.iter().enumerate() {
            let _ = write!(
                s,
                "    {{\"start\": {}, \"goal\": {}, \"path\": [",
                js(&a.start),
                js(&a.goal)
            );
            for (t, e) in a.path.iter().enumerate() {
                if t > 0 {
                    s.push(',');
                    s.push_str(if t % ELEMENTS_PER_LINE == 0 {
                        "\n      "
                    } else {
                        " "
                    });
                }
                s.push_str(&js(e));
            }
            s.push_str("]}");
            s.push_str(if i + 1 < self.agents.len() {
                ",\n"
            } else {
                "\n"
            });
        }
        s.push_str("  ]\n}\n");
        s
    }
}

/// The `claims` (a plan file's metrics) that differ from `actual` (the validator's metrics
/// serialised to a JSON object): `(key, claimed, actual)`. Keys not claimed, or claimed as `null`,
/// are not compared; floats are equal to a relative 1e-9 (files print them rounded by whatever
/// wrote them).
pub fn disputed(claims: &Map<String, Value>, actual: &Value) -> Vec<(String, Value, Value)> {
    let Some(actual) = actual.as_object() else {
        return Vec::new();
    };
    actual
        .iter()
        .filter_map(|(k, real)| {
            let claim = claims.get(k).filter(|c| !c.is_null())?;
            (!same_number(claim, real)).then(|| (k.clone(), claim.clone(), real.clone()))
        })
        .collect()
}

fn same_number(a: &Value, b: &Value) -> bool {
    match (a.as_f64(), b.as_f64()) {
        (Some(x), Some(y)) if a.is_f64() || b.is_f64() => {
            (x - y).abs() <= 1e-9 * x.abs().max(y.abs()).max(1.0)
        }
        _ => a == b,
    }
}

/// Refuses a plan file whose `family` (when it has one) is not `family`, before its paths are
/// read as that family's elements: `<path>: this is a <f> plan; ...`. Text that is not a JSON
/// object is left to the family's own parser (which names the line).
pub fn check_family(text: &str, family: &str, path: &Path) -> Result<()> {
    let Ok(Value::Object(o)) = serde_json::from_str::<Value>(text) else {
        return Ok(());
    };
    match o.get("family").and_then(Value::as_str) {
        Some(f) if !f.is_empty() && f != family => Err(Error::invalid(
            path,
            format!("this is a {f} plan, not a {family} plan (give that family's inputs)"),
        )),
        _ => Ok(()),
    }
}

/// Compact JSON of any serialisable value, with `, ` and `: ` separators (what a person reads).
fn js<T: Serialize + ?Sized>(v: &T) -> String {
    spaced(&serde_json::to_value(v).unwrap_or(Value::Null))
}

fn spaced(v: &Value) -> String {
    match v {
        Value::Array(a) => {
            let items: Vec<String> = a.iter().map(spaced).collect();
            format!("[{}]", items.join(", "))
        }
        Value::Object(o) => {
            let items: Vec<String> = o
                .iter()
                .map(|(k, v)| format!("{}: {}", Value::from(k.as_str()), spaced(v)))
                .collect();
            format!("{{{}}}", items.join(", "))
        }
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Envelope<[i64; 2]> {
        let mut extra = Map::new();
        extra.insert("note".into(), Value::from("x"));
        Envelope {
            format: FORMAT.into(),
            family: "grid".into(),
            world: World {
                kind: "grid-map".into(),
                file: "m.map".into(),
            },
            planner: "p".into(),
            params: BTreeMap::from([("w".to_string(), "8".to_string())]),
            seed: 3,
            solved: true,
            status: "solved".into(),
            rules: serde_json::json!({"goal": "stay", "following": true}),
            metrics: serde_json::json!({"makespan": 2})
                .as_object()
                .unwrap()
                .clone(),
            runtime_ms: 0.5,
            agents: vec![AgentPath {
                start: [0, 0],
                goal: [1, 0],
                path: (0..40).map(|t| [t, 0]).collect(),
            }],
            extra,
        }
    }

    #[test]
    fn round_trip_and_wrapping() {
        let e = sample();
        let text = e.to_json();
        assert!(text.lines().count() > 15, "{text}");
        let back: Envelope<[i64; 2]> = Envelope::parse(&text, Path::new("p.json")).unwrap();
        assert_eq!(back, e);
    }

    #[test]
    fn legacy_keys_are_kept_and_claims_compared() {
        let old = r#"{"map_file": "m.map", "planner": "x", "seed": 0, "solved": true,
            "goal_semantics": "stay", "metrics": {"sum_of_costs": 3, "makespan": null, "runtime_ms": 1.0},
            "agents": [{"start": [0, 0], "goal": [0, 0]}]}"#;
        let e: Envelope<[i64; 2]> = Envelope::parse(old, Path::new("o.json")).unwrap();
        assert_eq!(e.extra["map_file"], "m.map");
        assert!(e.agents[0].path.is_empty());
        let disputed = e.disputed_metrics(&serde_json::json!({"sum_of_costs": 4, "makespan": 1}));
        assert_eq!(disputed.len(), 1);
        assert_eq!(disputed[0].0, "sum_of_costs");
        let floats = serde_json::json!({"c": 92.93267227604592})
            .as_object()
            .unwrap()
            .clone();
        assert!(super::disputed(&floats, &serde_json::json!({"c": 92.93267227604593})).is_empty());
        assert_eq!(
            super::disputed(&floats, &serde_json::json!({"c": 92.94})).len(),
            1
        );
        let bad = Envelope::<u32>::parse(
            r#"{"format": "mrpp-plan/9", "solved": false, "agents": []}"#,
            Path::new("b.json"),
        );
        assert!(bad.unwrap_err().to_string().contains("mrpp-plan/9"));
        let e = Envelope::<u32>::parse("{\n\"solved\": 1}", Path::new("c.json")).unwrap_err();
        assert!(e.to_string().starts_with("c.json:2:"), "{e}");
    }
}
