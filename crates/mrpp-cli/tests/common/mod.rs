//! Helpers shared by the CLI test files (each includes this module with `mod common;`).

use std::path::Path;

/// Every `.svg` in `dir` (and its subfolders) parses and rasterises to a PNG with something drawn
/// on it: the experiments' figures are what a person will look at (issue 12). Returns how many
/// were checked.
#[allow(dead_code)]
pub fn every_svg_rasterises(dir: &Path) -> usize {
    let mut opt = resvg::usvg::Options::default();
    opt.fontdb_mut().load_system_fonts();
    let mut checked = 0;
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            if path.extension().is_none_or(|e| e != "svg") {
                continue;
            }
            let text = std::fs::read_to_string(&path).unwrap();
            let tree = resvg::usvg::Tree::from_str(&text, &opt)
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            let size = tree.size().to_int_size();
            let mut pixmap = resvg::tiny_skia::Pixmap::new(size.width(), size.height()).unwrap();
            resvg::render(
                &tree,
                resvg::tiny_skia::Transform::default(),
                &mut pixmap.as_mut(),
            );
            // More than a background: at least 3 colours on the picture.
            let mut colours = std::collections::HashSet::new();
            for p in pixmap.pixels() {
                colours.insert((p.red(), p.green(), p.blue(), p.alpha()));
                if colours.len() >= 3 {
                    break;
                }
            }
            assert!(colours.len() >= 3, "{}: nothing drawn", path.display());
            assert!(!pixmap.encode_png().unwrap().is_empty());
            checked += 1;
        }
    }
    checked
}
