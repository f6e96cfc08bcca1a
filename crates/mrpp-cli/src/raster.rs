//! Pictures as pixels (cargo feature `raster`, on by default): `mrpp render --out plan.png`
//! rasterises a family's SVG picture with resvg, and `--out plan.gif` (or `--gif`) animates the
//! viewer's scene ([`crate::view`]) as a GIF, one frame per time step (at most [`MAX_FRAMES`],
//! evenly spread), drawn by [`frame_svg`] the way the page draws it: obstacles, graph edges,
//! goals as hollow squares, agents as discs in the page's colours, the time step in a corner.
//! Text uses the system's fonts; without any, pictures have no text.

use serde_json::Value;

use crate::picture::{frame_svg, steps};

/// Frames of a GIF at most (longer plans skip steps evenly).
pub(crate) const MAX_FRAMES: usize = 300;

fn options() -> resvg::usvg::Options<'static> {
    let mut opt = resvg::usvg::Options::default();
    let db = opt.fontdb_mut();
    db.load_system_fonts();
    // `sans-serif` means Arial to resvg; use a sans face the system has (DejaVu Sans on Debian).
    let family = db
        .faces()
        .flat_map(|f| f.families.iter().map(|(name, _)| name.clone()))
        .find(|name| name.contains("Sans") && !name.contains("Mono"))
        .or_else(|| {
            db.faces()
                .find_map(|f| f.families.first().map(|(n, _)| n.clone()))
        });
    if let Some(family) = family {
        db.set_sans_serif_family(family);
    }
    opt
}

/// `svg` as RGBA pixels (premultiplied), with its size.
fn rasterise(svg: &str, opt: &resvg::usvg::Options) -> Result<resvg::tiny_skia::Pixmap, String> {
    let tree = resvg::usvg::Tree::from_str(svg, opt).map_err(|e| format!("bad SVG: {e}"))?;
    let size = tree.size().to_int_size();
    let mut pixmap = resvg::tiny_skia::Pixmap::new(size.width().max(1), size.height().max(1))
        .ok_or("picture too large")?;
    pixmap.fill(resvg::tiny_skia::Color::WHITE);
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::default(),
        &mut pixmap.as_mut(),
    );
    Ok(pixmap)
}

/// PNG bytes of an SVG picture.
pub(crate) fn png(svg: &str) -> Result<Vec<u8>, String> {
    rasterise(svg, &options())?
        .encode_png()
        .map_err(|e| format!("PNG encoding failed: {e}"))
}

/// An animated GIF of the scene: one frame per step (at most [`MAX_FRAMES`]), 5 frames a second,
/// looping.
pub(crate) fn gif(scene: &Value) -> Result<Vec<u8>, String> {
    let opt = options();
    let steps = steps(scene);
    let frames = (steps + 1).min(MAX_FRAMES);
    let mut out = Vec::new();
    {
        let first = rasterise(&frame_svg(scene, 0), &opt)?;
        let (w, h) = (first.width(), first.height());
        let (w16, h16) = (
            u16::try_from(w).map_err(|_| "picture too wide for a GIF")?,
            u16::try_from(h).map_err(|_| "picture too tall for a GIF")?,
        );
        let mut enc = gif::Encoder::new(&mut out, w16, h16, &[]).map_err(|e| e.to_string())?;
        enc.set_repeat(gif::Repeat::Infinite)
            .map_err(|e| e.to_string())?;
        for k in 0..frames {
            let t = if frames > 1 {
                k * steps / (frames - 1)
            } else {
                0
            };
            let pixmap = if k == 0 {
                first.clone()
            } else {
                rasterise(&frame_svg(scene, t), &opt)?
            };
            let mut rgba = pixmap.take();
            let mut frame = gif::Frame::from_rgba_speed(w16, h16, &mut rgba, 10);
            frame.delay = 20;
            enc.write_frame(&frame).map_err(|e| e.to_string())?;
        }
    }
    Ok(out)
}
