//! `mrpp view`: one self-contained HTML page (the world and the plan embedded, no network) that
//! plays a plan in any browser, written to a file or served on 127.0.0.1.
//!
//! A family turns its files into a *scene* (JSON), the one thing the page reads:
//!
//! ```text
//! { "family", "title", "about",
//!   "unit": "tick"                       runs in ticks (lifelong --ticks, `mrpp execute` records);
//!                                        absent: a path index is a "step"
//!   "bounds": [x0, y0, x1, y1],          world units; "y_up": true flips the y axis
//!   "cells": {"width", "height", "rows": ["#..", ...]}      grids: '#' blocked
//!   "polygons": [[[x, y], ...], ...],    obstacles
//!   "segments": [[[x, y], [x, y]], ...], "nodes": [[x, y], ...]   graphs (trees): edges, nodes
//!   "agents": [{"radius", "start": [x, y], "goal": [x, y], "path": [[x, y], ...]}],
//!             grids give "cells": [y * width + x, ...] instead of "path" (cell centres);
//!             lifelong runs add change lists, each entry holding from its step on:
//!             "goals": [[t, cell or -1, task id or -1], ...], "headings": [[t, 0..3], ...];
//!             executed records (`mrpp execute`) and lifelong runs in ticks add "held":
//!             [[t, 1 | 0], ...] (a delay holds it)
//!   "series": {"name", "values": [one per step]}   drawn as a small chart (lifelong: tasks finished)
//!   "verdict": {"valid": true, "metrics": {...}} | {"valid": false, "text", "conflict"?: {"t", "agents", "at"}} }
//! ```
//!
//! Path index = time step; an agent rests on its last point. The page (`assets/view.html`) draws
//! on one canvas (no DOM node per agent), interpolates between steps, and keeps its state in
//! `window.mrppView` (time, positions, screen mapping) for browser tests.

use std::io::{Read, Write};
use std::net::TcpListener;
use std::path::{Path, PathBuf};

use crate::family::{Inputs, family_of_inputs};
use crate::output::{Fail, out, say, write_atomic};

/// The page, with `__MRPP_SCENE__` where the scene goes.
const PAGE: &str = include_str!("../assets/view.html");

/// The page for `scene`.
pub(crate) fn page(scene: &serde_json::Value) -> String {
    // Inside <script>, "</" would end the element early.
    let data = scene.to_string().replace("</", "<\\/");
    PAGE.replace("__MRPP_SCENE__", &data)
}

/// `mrpp view`: writes the page to `out` (default: the plan's name with `.html`), and with
/// `serve` serves it on 127.0.0.1:`port` (0: any free port) until interrupted.
pub(crate) fn view(
    inputs: &Inputs,
    plan: &Path,
    out: Option<PathBuf>,
    serve: bool,
    port: u16,
) -> Result<u8, Fail> {
    let out = (!serve || out.is_some()).then(|| out.unwrap_or_else(|| plan.with_extension("html")));
    if let Some(out) = &out {
        inputs.guard(&[plan], &[out])?;
    }
    let scene = if crate::execute_cmd::is_execution_record(plan) {
        crate::execute_cmd::scene(inputs, plan)?
    } else {
        let inputs = &crate::verbs::with_plan_kind(inputs, plan);
        let family = family_of_inputs(inputs)?;
        crate::verbs::warn_if_invalid(family, inputs, plan);
        family.scene(inputs, plan)?
    };
    let html = page(&scene);
    if let Some(out) = out {
        write_atomic(&out, &html)?;
        say!("viewer written to {} (open it in a browser)", out.display());
    }
    if serve {
        let listener = TcpListener::bind(("127.0.0.1", port))
            .map_err(|e| Fail(format!("cannot listen on 127.0.0.1:{port}: {e}")))?;
        let addr = listener
            .local_addr()
            .map_err(|e| Fail(format!("cannot read the listening address: {e}")))?;
        out!("serving the viewer on http://{addr}/ (Ctrl-C stops)");
        let _ = std::io::stdout().flush();
        for stream in listener.incoming() {
            let Ok(mut s) = stream else { continue };
            let mut buf = [0u8; 4096];
            let _ = s.read(&mut buf);
            let header = format!(
                "HTTP/1.1 200 OK\r\nContent-Type: text/html; charset=utf-8\r\nContent-Length: {}\r\nCache-Control: no-store\r\nConnection: close\r\n\r\n",
                html.len()
            );
            let _ = s.write_all(header.as_bytes());
            let _ = s.write_all(html.as_bytes());
        }
    }
    Ok(0)
}
