//! The League of Robot Runners' action models: robot states, actions, their letters, and one
//! robot's move (League of Robot Runners start kit v2.1.2, `inc/ActionModel.h`,
//! `src/ActionModel.cpp`; `docs/lorr-semantics.md` §2).
//!
//! - `MAPF_T` (the kit's only model): a state is a cell and an orientation (0 east, 1 south,
//!   2 west, 3 north; every robot starts facing east); `F` moves one cell forward, `R` turns
//!   clockwise (east to south), `C` counter-clockwise, `W` waits, `T` (no action: a timeout or a
//!   missing entry) behaves as a wait.
//! - `MAPF` (mrpp's option for the plain 4-neighbour model; the kit never runs it, PlanViz draws
//!   it): `L` and `R` move one cell left (column - 1) and right, and, as PlanViz reads them
//!   (v2.1.0 to v3.1.0, `script/util.py` `state_transition_mapf`), `U` moves to row + 1 (down on
//!   the screen) and `D` to row - 1; `W` waits, `T` as above. The orientation stays east.
//!
//! A move that leaves the map (the kit's linearised `F` off an east or west edge would wrap into
//! the next row; the kit refuses it as a jump of more than one cell) or enters an obstacle is
//! refused as an "unallowed move".

use std::fmt;

use mrpp_core::mapf::graph::VertexId;
use mrpp_mapf::GridMap;

/// Which moves robots have (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ActionModel {
    /// 4-neighbour moves and wait, no orientation (`"MAPF"`).
    Mapf,
    /// Orientation; forward, clockwise, counter-clockwise, wait (`"MAPF_T"`, the kit's model).
    #[default]
    MapfT,
}

impl ActionModel {
    /// The name LoRR's output JSON uses (`actionModel`).
    pub fn name(self) -> &'static str {
        match self {
            ActionModel::Mapf => "MAPF",
            ActionModel::MapfT => "MAPF_T",
        }
    }

    /// The model named `name` (`MAPF` or `MAPF_T`, any case).
    pub fn parse(name: &str) -> Option<ActionModel> {
        match name.to_ascii_uppercase().as_str() {
            "MAPF" => Some(ActionModel::Mapf),
            "MAPF_T" => Some(ActionModel::MapfT),
            _ => None,
        }
    }
}

/// A robot's orientation (`MAPF_T`): 0 east, 1 south, 2 west, 3 north, as in the kit.
pub type Orientation = u8;

/// East, every robot's orientation at the start (the kit's agent file cannot set it).
pub const EAST: Orientation = 0;

/// Where a robot is: a vertex of the map's graph and its orientation (always [`EAST`] under
/// `MAPF`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct State {
    /// The vertex (a free cell).
    pub vertex: VertexId,
    /// The orientation.
    pub orientation: Orientation,
}

/// One robot's action for one step (module doc for the letters).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Action {
    /// `F`: one cell forward (`MAPF_T`).
    Forward,
    /// `R`: turn clockwise (`MAPF_T`).
    Clockwise,
    /// `C`: turn counter-clockwise (`MAPF_T`).
    CounterClockwise,
    /// `R`/`U`/`L`/`D` (`MAPF`): one cell in direction `d` (0 east, 1 south = row + 1, 2 west,
    /// 3 north), letters as PlanViz reads them (module doc).
    Move(Orientation),
    /// `W`: wait.
    Wait,
    /// `T`: no action (a late planner's step or a missing entry); behaves as a wait.
    NoAction,
}

impl Action {
    /// The letter LoRR's output JSON writes for this action under `model`.
    pub fn letter(self) -> char {
        match self {
            Action::Forward => 'F',
            Action::Clockwise => 'R',
            Action::CounterClockwise => 'C',
            Action::Move(0) => 'R',
            Action::Move(1) => 'U',
            Action::Move(2) => 'L',
            Action::Move(_) => 'D',
            Action::Wait => 'W',
            Action::NoAction => 'T',
        }
    }

    /// The action `letter` stands for under `model`.
    pub fn from_letter(model: ActionModel, letter: char) -> Option<Action> {
        Some(match (model, letter) {
            (_, 'W') => Action::Wait,
            (_, 'T') => Action::NoAction,
            (ActionModel::MapfT, 'F') => Action::Forward,
            (ActionModel::MapfT, 'R') => Action::Clockwise,
            (ActionModel::MapfT, 'C') => Action::CounterClockwise,
            (ActionModel::Mapf, 'R') => Action::Move(0),
            (ActionModel::Mapf, 'U') => Action::Move(1),
            (ActionModel::Mapf, 'L') => Action::Move(2),
            (ActionModel::Mapf, 'D') => Action::Move(3),
            _ => return None,
        })
    }

    /// True for the actions of `model`.
    pub fn belongs_to(self, model: ActionModel) -> bool {
        match self {
            Action::Wait | Action::NoAction => true,
            Action::Forward | Action::Clockwise | Action::CounterClockwise => {
                model == ActionModel::MapfT
            }
            Action::Move(d) => model == ActionModel::Mapf && d < 4,
        }
    }
}

impl fmt::Display for Action {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.letter())
    }
}

/// The neighbour of `v` in direction `d` (0 east, 1 south, 2 west, 3 north), if it is a free cell.
pub fn neighbour(map: &GridMap, v: VertexId, d: Orientation) -> Option<VertexId> {
    let (x, y) = map.cell(v);
    let (x, y) = (i64::from(x), i64::from(y));
    let (nx, ny) = match d {
        0 => (x + 1, y),
        1 => (x, y + 1),
        2 => (x - 1, y),
        _ => (x, y - 1),
    };
    map.vertex_at(nx, ny)
}

/// The direction from `v` to its neighbour `w` (0 east, 1 south, 2 west, 3 north).
pub fn direction(map: &GridMap, v: VertexId, w: VertexId) -> Option<Orientation> {
    (0..4).find(|&d| neighbour(map, v, d) == Some(w))
}

/// The state after `action` from `s`, or `None` when it leaves the map or enters an obstacle
/// ("unallowed move"). `action` must belong to the model (checked by the caller).
pub fn apply(map: &GridMap, s: State, action: Action) -> Option<State> {
    match action {
        Action::Wait | Action::NoAction => Some(s),
        Action::Clockwise => Some(State {
            orientation: (s.orientation + 1) % 4,
            ..s
        }),
        Action::CounterClockwise => Some(State {
            orientation: (s.orientation + 3) % 4,
            ..s
        }),
        Action::Forward => {
            neighbour(map, s.vertex, s.orientation).map(|vertex| State { vertex, ..s })
        }
        Action::Move(d) => neighbour(map, s.vertex, d).map(|vertex| State { vertex, ..s }),
    }
}

/// Rotations needed to turn from `from` to `to` (0, 1 or 2).
pub fn turns(from: Orientation, to: Orientation) -> u32 {
    let d = (i32::from(to) - i32::from(from)).rem_euclid(4);
    if d == 3 { 1 } else { d as u32 }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map() -> GridMap {
        GridMap::from_free_rows(&[vec![true, true, false], vec![true, true, true]])
    }

    #[test]
    fn letters_round_trip_per_model() {
        for model in [ActionModel::Mapf, ActionModel::MapfT] {
            for c in "FRCUDLWT".chars() {
                if let Some(a) = Action::from_letter(model, c) {
                    assert!(a.belongs_to(model));
                    assert_eq!(a.letter(), c);
                }
            }
        }
        assert_eq!(Action::from_letter(ActionModel::Mapf, 'F'), None);
        assert_eq!(Action::from_letter(ActionModel::MapfT, 'U'), None);
    }

    #[test]
    fn moves_turns_and_refusals() {
        let m = map();
        let v = |x, y| m.vertex_at(x, y).unwrap();
        let s = State {
            vertex: v(0, 0),
            orientation: EAST,
        };
        assert_eq!(apply(&m, s, Action::Forward).unwrap().vertex, v(1, 0));
        let south = apply(&m, s, Action::Clockwise).unwrap();
        assert_eq!(south.orientation, 1);
        assert_eq!(apply(&m, south, Action::Forward).unwrap().vertex, v(0, 1));
        let north = apply(&m, s, Action::CounterClockwise).unwrap();
        assert_eq!(north.orientation, 3);
        assert_eq!(apply(&m, north, Action::Forward), None, "off the map");
        let east_of_1 = State {
            vertex: v(1, 0),
            orientation: EAST,
        };
        assert_eq!(apply(&m, east_of_1, Action::Forward), None, "an obstacle");
        let east_edge = State {
            vertex: v(2, 1),
            orientation: EAST,
        };
        assert_eq!(apply(&m, east_edge, Action::Forward), None, "no wrap");
        assert_eq!(apply(&m, s, Action::Move(1)).unwrap().vertex, v(0, 1));
        assert_eq!(turns(0, 3), 1);
        assert_eq!(turns(0, 2), 2);
        assert_eq!(direction(&m, v(0, 0), v(0, 1)), Some(1));
    }
}
