//! mrpp-exec: plans executed tick by tick on robots that are late (issue 29). A grid plan's moves
//! take `ticks_per_move` ticks each (the League of Robot Runners' `agentCounter`); seeded delays
//! ([`delays`], the League's `delayConfig` models) hold robots; an executor decides when each
//! robot starts its next move: the action dependency graph ([`adg`]; Hönig et al., RA-L 2019),
//! which keeps the plan's order of passage at every cell however late a robot is, or `naive`,
//! which follows the plan's timing and may collide. [`execute()`] runs it and measures it (executed
//! over planned makespan and sum of costs, ticks lost to delays, waits added, footprint
//! collisions); [`check`] replays an executed record independently of the executor.

pub mod adg;
pub mod check;
pub mod delays;
pub mod execute;
pub mod replan;
pub mod robust;

pub use adg::Adg;
pub use delays::{DelayConfig, DelayGenerator};
pub use execute::{ExecConfig, Execution, ExecutorKind, execute, execute_replanning};
pub use replan::{Replanner, Replanning};
