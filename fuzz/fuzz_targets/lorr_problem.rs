//! League of Robot Runners problems (`lorr::parse_with`): the input is the problem JSON, the map,
//! the agent file and the task file, separated by lines `----`; the JSON's file names are ignored
//! and each file read gets its part (a missing part reads as empty).
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|text: &str| {
    let parts: Vec<&str> = text.split("\n----\n").collect();
    let part = |i: usize| parts.get(i).copied().unwrap_or("").to_string();
    let read = |p: &Path| -> mrpp_core::error::Result<String> {
        Ok(match p.file_name().and_then(|f| f.to_str()) {
            Some("m.map") => part(1),
            Some("a.agents") => part(2),
            _ => part(3),
        })
    };
    // The JSON's own file names are replaced so that the reads above find their parts.
    let json = match serde_json::from_str::<serde_json::Value>(&part(0)) {
        Ok(serde_json::Value::Object(mut o)) => {
            o.insert("mapFile".into(), "m.map".into());
            o.insert("agentFile".into(), "a.agents".into());
            o.insert("taskFile".into(), "t.tasks".into());
            serde_json::Value::Object(o).to_string()
        }
        _ => part(0),
    };
    let _ = mrpp_grid::lorr::parse_with(&json, Path::new("fuzz.json"), &read);
});
