//! The one agent palette of every mrpp picture and of the viewer page (`mrpp view`): agent `i`'s
//! hue advances by the golden angle (137.508°), saturation 70%, and the lightness cycles through
//! three bands (45%, 32%, 58%) every 7 agents, so neighbours in id order differ in hue and
//! agents whose hues come close again differ in lightness. The page computes the same
//! `hsl(137.508 i, 70%, l)` in JavaScript; a test pins the values here to Python's
//! `colorsys.hls_to_rgb`.

/// Agent `i`'s colour as `#rrggbb` (hex, because not every SVG consumer reads `hsl()`).
pub fn agent_colour(i: usize) -> String {
    let h = (i as f64 * 137.508) % 360.0 / 360.0;
    let (s, l) = (0.7, [0.45, 0.32, 0.58][(i / 7) % 3]);
    let q = if l < 0.5 {
        l * (1.0 + s)
    } else {
        l + s - l * s
    };
    let p = 2.0 * l - q;
    let ch = |t: f64| {
        let t = t.rem_euclid(1.0);
        if t < 1.0 / 6.0 {
            p + (q - p) * 6.0 * t
        } else if t < 0.5 {
            q
        } else if t < 2.0 / 3.0 {
            p + (q - p) * (2.0 / 3.0 - t) * 6.0
        } else {
            p
        }
    };
    let c = |x: f64| (x * 255.0).round() as u8;
    format!(
        "#{:02x}{:02x}{:02x}",
        c(ch(h + 1.0 / 3.0)),
        c(ch(h)),
        c(ch(h - 1.0 / 3.0))
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colours_match_the_page_and_do_not_repeat() {
        // The page's hsl(137.508 i, 70%, l) for agents 0, 1 and 9 (lightness 45%, 45%, 32%), as
        // Python's colorsys.hls_to_rgb gives them.
        assert_eq!(agent_colour(0), "#c32222");
        assert_eq!(agent_colour(1), "#22c351");
        assert_eq!(agent_colour(9), "#188b60");
        let cs: Vec<String> = (0..64).map(agent_colour).collect();
        for (i, c) in cs.iter().enumerate() {
            assert!(c.len() == 7 && c.starts_with('#'), "{c}");
            assert!(!cs[..i].contains(c), "colour {i} repeats");
        }
    }
}
