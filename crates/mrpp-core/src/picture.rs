//! What every mrpp picture shares: the agents' colours and where they wait.
//!
//! The palette is also the viewer page's (`mrpp view`): agent `i`'s hue advances by the golden angle (137.508°), saturation 70%, and the lightness cycles through
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

/// The waits of a path (one entry per time step): each run of steps at which the agent stays
/// where it is, before its last move, as `(first step, steps)`. Staying at the end is arrival,
/// not waiting.
pub fn wait_runs<T: PartialEq>(path: &[T]) -> Vec<(usize, usize)> {
    let Some(last_move) = (1..path.len()).rev().find(|&k| path[k] != path[k - 1]) else {
        return Vec::new();
    };
    let mut runs = Vec::new();
    let mut k = 0;
    while k < last_move {
        if path[k + 1] == path[k] {
            let from = k;
            while k < last_move && path[k + 1] == path[k] {
                k += 1;
            }
            runs.push((from, k - from));
        } else {
            k += 1;
        }
    }
    runs
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn waits_are_runs_of_still_steps_before_the_last_move() {
        assert_eq!(wait_runs(&[0, 0, 0, 1, 1, 2, 2, 2]), vec![(0, 2), (3, 1)]);
        assert_eq!(wait_runs(&[5, 6, 6, 5, 5]), vec![(1, 1)]);
        assert!(wait_runs(&[3, 3]).is_empty());
        assert!(wait_runs::<u32>(&[]).is_empty());
        let p = [[0.0, 0.0], [0.0, 0.0], [1.0, 0.0]];
        assert_eq!(wait_runs(&p), vec![(0, 1)]);
    }

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
