//! Delay settings as a user or a problem file gives them: mrpp's `--delays` spec
//! (`mrpp_exec::DelayConfig::parse`, whose accepted specs must read back from their own
//! `spec()`), and a League of Robot Runners problem's `agentCounter`, `agentSize` and
//! `delayConfig` (`mrpp_lifelong::execution::ExecutionModel::of_problem`), then a short run in
//! ticks under what was accepted: no panic on any input.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;
use std::time::Duration;

use mrpp_core::{Ctx, solve};
use mrpp_exec::DelayConfig;
use mrpp_lifelong::execution::ExecutionModel;
use mrpp_lifelong::{ActionModel, LifelongProblem, PLANNERS};

fuzz_target!(|text: &str| {
    if let Ok(cfg) = DelayConfig::parse(text) {
        let again = DelayConfig::parse(&cfg.spec()).expect("a spec reads back");
        assert_eq!(again.spec(), cfg.spec());
    }
    let read = |p: &Path| -> mrpp_core::error::Result<String> {
        Ok(match p.file_name().and_then(|f| f.to_str()) {
            Some("m.map") => "type octile\nheight 3\nwidth 4\nmap\n....\n.@..\n....\n".into(),
            Some("a.agents") => "2\n0\n3\n".into(),
            _ => "3\n2,11\n8\n4,7,0\n".into(),
        })
    };
    let json = format!(
        r#"{{"mapFile": "m.map", "agentFile": "a.agents", "taskFile": "t.tasks", "teamSize": 2, "numTasksReveal": 1.5, {text}}}"#
    );
    let Ok(files) = mrpp_mapf::lorr_files::parse_with(&json, Path::new("p.json"), &read) else {
        return;
    };
    let Ok(model) = ExecutionModel::of_problem(&files) else {
        return;
    };
    let problem = LifelongProblem::new(files, ActionModel::MapfT, 40, Duration::from_secs(1))
        .with_execution(model);
    let planner = PLANNERS[0].instantiate(&[]).expect("default parameters");
    solve(planner.as_ref(), &problem, &Ctx::default()).expect("a valid run in ticks");
});
