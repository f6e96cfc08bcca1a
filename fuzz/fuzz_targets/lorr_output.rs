//! League of Robot Runners output JSON read back as a lifelong trace
//! (`mrpp_lifelong::lorr_output::from_json`) against a fixed small problem (a 4 x 3 map, two
//! robots, three tasks), then replayed by the validator: no panic on any input.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;
use std::sync::OnceLock;
use std::time::Duration;

use mrpp_core::Problem;
use mrpp_lifelong::{ActionModel, LifelongProblem};

fn problem(model: ActionModel) -> LifelongProblem {
    let read = |p: &Path| -> mrpp_core::error::Result<String> {
        Ok(match p.file_name().and_then(|f| f.to_str()) {
            Some("m.map") => "type octile\nheight 3\nwidth 4\nmap\n....\n.@..\n....\n".into(),
            Some("a.agents") => "2\n0\n3\n".into(),
            _ => "3\n2,11\n8\n4,7,0\n".into(),
        })
    };
    let json = r#"{"mapFile": "m.map", "agentFile": "a.agents", "taskFile": "t.tasks", "teamSize": 2, "numTasksReveal": 1.5}"#;
    let files = mrpp_mapf::lorr_files::parse_with(json, Path::new("p.json"), &read)
        .expect("the fixed problem reads");
    LifelongProblem::new(files, model, 64, Duration::from_secs(1))
}

fuzz_target!(|text: &str| {
    static PROBLEMS: OnceLock<[LifelongProblem; 2]> = OnceLock::new();
    let problems =
        PROBLEMS.get_or_init(|| [problem(ActionModel::MapfT), problem(ActionModel::Mapf)]);
    for p in problems {
        if let Ok((trace, _)) =
            mrpp_lifelong::lorr_output::from_json(p, text, Path::new("out.json"))
        {
            if let Ok(m) = p.validate(&trace) {
                // A valid trace writes back and reads to the same count.
                let json =
                    mrpp_lifelong::lorr_output::to_json(p, &trace).expect("valid traces write");
                assert_eq!(json["numTaskFinished"], m.tasks_finished);
            }
        }
    }
});
