//! The verbs every family shares, each written once: the family comes from the planner name
//! (`solve`) or from the inputs (`validate`, `info`, `render`).

use std::path::Path;

use crate::family::{Inputs, SolveRequest, family_of_inputs, family_of_planner};
use crate::output::{Fail, say, write_atomic};

/// `mrpp solve`: plans, exit 0 solved (a valid plan), 3 not solved, 1 bad input or an invalid
/// plan (a bug).
pub(crate) fn solve(req: &SolveRequest) -> Result<u8, Fail> {
    let family = family_of_planner(&req.planner)?;
    if family.name() == mrpp_lifelong::FAMILY && req.inputs.lorr.is_some() && !req.inputs.lifelong {
        // A lifelong planner on a `--lorr` problem runs it lifelong.
        let mut inputs = req.inputs.clone();
        inputs.lifelong = true;
        return family.solve(&SolveRequest {
            inputs,
            ..req.clone()
        });
    }
    family.solve(req)
}

/// `inputs`, made lifelong when they name a `--lorr` problem and `plan` is LoRR output JSON (a
/// lifelong run's file, mrpp's or the League's start kit's).
pub(crate) fn with_plan_kind(inputs: &Inputs, plan: &Path) -> Inputs {
    let mut inputs = inputs.clone();
    if inputs.lorr.is_some() && !inputs.lifelong && crate::lifelong_family::is_lorr_output(plan) {
        inputs.lifelong = true;
    }
    inputs
}

/// `mrpp validate`: exit 0 when the plan is valid, 1 naming the first violation.
pub(crate) fn validate(inputs: &Inputs, plan: &Path) -> Result<u8, Fail> {
    let inputs = &with_plan_kind(inputs, plan);
    family_of_inputs(inputs)?.validate(inputs, plan)
}

/// `mrpp info`: what the family can say about an instance (sizes, lower bounds).
pub(crate) fn info(inputs: &Inputs) -> Result<u8, Fail> {
    family_of_inputs(inputs)?.info(inputs)
}

/// `mrpp render`: a picture of a plan, by `out`'s extension: `.svg` (the family's picture),
/// `.png` (that picture rasterised) or `.gif` (the plan animated; `gif` asks for it explicitly).
/// An unknown extension is refused before anything is read.
pub(crate) fn render(inputs: &Inputs, plan: &Path, out: &Path, gif: bool) -> Result<u8, Fail> {
    let ext = out
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    if gif && ext != "gif" {
        return Err(Fail(format!(
            "{}: --gif writes an animated GIF, so --out must end in .gif",
            out.display()
        )));
    }
    if !["svg", "png", "gif"].contains(&ext.as_str()) {
        return Err(Fail(format!(
            "{}: unknown picture format `.{ext}` (use .svg, .png or .gif)",
            out.display()
        )));
    }
    inputs.guard(&[plan], &[out])?;
    let inputs = &with_plan_kind(inputs, plan);
    let family = family_of_inputs(inputs)?;
    warn_if_invalid(family, inputs, plan);
    match ext.as_str() {
        "svg" => write_atomic(out, &family.render(inputs, plan)?)?,
        #[cfg(feature = "raster")]
        "png" => {
            let png = crate::raster::png(&family.render(inputs, plan)?)
                .map_err(|e| Fail(format!("{}: {e}", out.display())))?;
            write_atomic(out, &png)?;
        }
        #[cfg(feature = "raster")]
        "gif" => {
            let scene = family.scene(inputs, plan)?;
            let live = crate::progress::Live::start("render GIF");
            let report = live.callback();
            let gif = crate::raster::gif(&scene, &|done, total| {
                report(&mrpp_core::Progress {
                    stage: "frame",
                    done: done as u64,
                    total: total as u64,
                    note: String::new(),
                })
            });
            live.finish();
            let gif = gif.map_err(|e| Fail(format!("{}: {e}", out.display())))?;
            write_atomic(out, &gif)?;
        }
        _ => {
            return Err(Fail(format!(
                "{}: .{ext} pictures need mrpp built with the `raster` feature",
                out.display()
            )));
        }
    }
    say!("picture written to {}", out.display());
    Ok(0)
}

/// The `status` of a JSON plan file that says `solved: false` (`None` for anything else).
pub(crate) fn unsolved_status(plan: &Path) -> Option<String> {
    let text = std::fs::read_to_string(plan).ok()?;
    if !text.trim_start().starts_with('{') {
        return None;
    }
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    (v.get("solved")? == &serde_json::Value::Bool(false)).then(|| {
        v.get("status")
            .and_then(serde_json::Value::as_str)
            .unwrap_or("unknown")
            .to_string()
    })
}

/// Says on stderr when the plan to be drawn or played breaks a rule (or its claims do not hold):
/// the picture is still made, since a broken plan is worth seeing, but not without a word.
pub(crate) fn warn_if_invalid(family: &dyn crate::family::Family, inputs: &Inputs, plan: &Path) {
    if let Some(status) = unsolved_status(plan) {
        // Every family's pictures draw the starts and goals of such a file.
        eprintln!(
            "mrpp: note: {}: the file holds no plan (solved=false, status {status}): only the starts and goals can be drawn",
            plan.display()
        );
        return;
    }
    if let Err(Fail(why)) = family.check(inputs, plan) {
        eprintln!("mrpp: warning: this plan is not valid (drawn as it is): {why}");
    }
}
