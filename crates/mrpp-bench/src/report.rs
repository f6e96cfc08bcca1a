//! What the paper pages share: figures drawn with plotters (SVG backend only, so no system font
//! libraries are needed) and CSV text.

use plotters::prelude::*;

/// One line of a panel: `(x, y)` points, drawn solid (ours) or as hollow markers (the paper's).
#[derive(Default)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    pub paper: bool,
    /// Error bars: ± this much around each point (the standard deviation); empty = none.
    pub spread: Vec<f64>,
}

/// One panel of a figure.
pub struct Panel {
    pub title: String,
    pub series: Vec<Series>,
}

/// The tab10 colours: one per series name, up to ten names per figure.
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Height of one legend row, in pixels.
const LEGEND_ROW_PX: u32 = 22;

/// A tick label for `v` on an axis spanning `span`: as many decimals as the span needs (two
/// significant digits of the span), trailing zeros cut.
fn tick_label(v: f64, span: f64) -> String {
    let decimals = if span > 0.0 {
        (1.0 - span.log10().floor()).clamp(0.0, 6.0) as usize
    } else {
        2
    };
    let t = format!("{v:.decimals$}");
    let t = if t.contains('.') {
        t.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        t
    };
    if t == "-0" { "0".into() } else { t }
}

/// Panels side by side, x = `x_desc`, y = `y_desc`. Series with the same name share a colour.
pub fn line_panels(
    title: &str,
    x_desc: &str,
    y_desc: &str,
    panels: &[Panel],
) -> Result<String, String> {
    line_panels_with(title, &vec![(x_desc, y_desc); panels.len()], panels)
}

/// [`line_panels`] with each panel's own axis descriptions, `axes[k] = (x, y)` for `panels[k]`.
/// Series drawn on top of each other stay visible: in a panel of up to four lines of ours, the
/// first is drawn widest and each next one narrower (three planners at 100% show as nested
/// bands, not one line).
pub fn line_panels_with(
    title: &str,
    axes: &[(&str, &str)],
    panels: &[Panel],
) -> Result<String, String> {
    let mut svg = String::new();
    let err = |e: &dyn std::fmt::Display| e.to_string();
    {
        let width = (420 * panels.len().max(1) as u32).max(640);
        let root = SVGBackend::with_string(&mut svg, (width, 450)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(&e))?;
        let root = root
            .titled(title, ("sans-serif", 20))
            .map_err(|e| err(&e))?;
        let mut names: Vec<&str> = Vec::new();
        for p in panels {
            for s in &p.series {
                let base = s.name.trim_end_matches(" (paper)");
                if !names.contains(&base) {
                    names.push(base);
                }
            }
        }
        let colour = |name: &str| {
            let base = name.trim_end_matches(" (paper)");
            PALETTE[names.iter().position(|n| *n == base).unwrap_or(0) % PALETTE.len()]
        };
        // The legend in a band of its own above the panels, so it never covers data: a line per
        // series of ours, a hollow circle per series of the paper's, in rows as wide as the
        // figure.
        let mut entries: Vec<(String, bool)> = Vec::new();
        for p in panels {
            for s in &p.series {
                if !entries.iter().any(|(n, _)| *n == s.name) {
                    entries.push((s.name.clone(), s.paper));
                }
            }
        }
        let entry_width = |name: &str| 40 + 7 * name.chars().count() as i32;
        let mut placed: Vec<(i32, i32)> = Vec::new();
        let (mut x, mut row) = (12i32, 0i32);
        for (name, _) in &entries {
            if x > 12 && x + entry_width(name) > width as i32 - 12 {
                (x, row) = (12, row + 1);
            }
            placed.push((x, row * LEGEND_ROW_PX as i32));
            x += entry_width(name);
        }
        let rows = placed
            .last()
            .map_or(1, |&(_, y)| y as u32 / LEGEND_ROW_PX + 1);
        let (band, plots) = root.split_vertically(8 + LEGEND_ROW_PX * rows);
        for ((name, paper), &(x, y)) in entries.iter().zip(&placed) {
            let c = colour(name);
            let mid = y + 15;
            if *paper {
                band.draw(&Circle::new((x + 10, mid), 4, c.stroke_width(1)))
                    .map_err(|e| err(&e))?;
            } else {
                band.draw(&PathElement::new(
                    vec![(x, mid), (x + 20, mid)],
                    c.stroke_width(2),
                ))
                .map_err(|e| err(&e))?;
            }
            band.draw(&Text::new(
                name.clone(),
                (x + 26, y + 8),
                ("sans-serif", 12),
            ))
            .map_err(|e| err(&e))?;
        }
        // Integer x values (agents, robots, steps) get integer tick labels.
        let integer_x = panels.iter().all(|p| {
            p.series
                .iter()
                .all(|s| s.points.iter().all(|(x, _)| x.fract() == 0.0))
        });
        for ((area, panel), &(x_desc, y_desc)) in plots
            .split_evenly((1, panels.len().max(1)))
            .iter()
            .zip(panels)
            .zip(axes.iter().chain(std::iter::repeat(&("", ""))))
        {
            let ours = panel.series.iter().filter(|s| !s.paper).count();
            let mut drawn = 0u32;
            let (mut x0, mut x1, mut y1) = (f64::MAX, f64::MIN, 0f64);
            for s in &panel.series {
                for (k, &(x, y)) in s.points.iter().enumerate() {
                    x0 = x0.min(x);
                    x1 = x1.max(x);
                    y1 = y1.max(y + s.spread.get(k).copied().unwrap_or(0.0));
                }
            }
            if x0 > x1 {
                (x0, x1) = (0.0, 1.0);
            }
            // A margin of 5% of the span (half a step on integer axes) on both sides, cut at zero
            // for data that start above it (so no negative ticks for non-negative data).
            let pad = if integer_x {
                ((x1 - x0) * 0.05).max(0.5)
            } else if x1 > x0 {
                (x1 - x0) * 0.05
            } else {
                0.05 * x0.abs().max(1.0)
            };
            // Fractional data starting at zero start the axis at zero too (a delay probability
            // of 0 is not "-0.04"); integer axes keep half a step before their first value.
            let left = if (x0 > 0.0 || (x0 == 0.0 && !integer_x)) && x0 - pad < 0.0 {
                0.0
            } else {
                x0 - pad
            };
            let top = (y1 * 1.15).max(1.0);
            // Every y tick with the same decimals: one below 10, none above.
            let y_decimals = if top < 10.0 { 1 } else { 0 };
            let mut chart = ChartBuilder::on(area)
                .caption(&panel.title, ("sans-serif", 16))
                .margin(12)
                .x_label_area_size(32)
                .y_label_area_size(60)
                .build_cartesian_2d(left..(x1 + pad), 0f64..top)
                .map_err(|e| err(&e))?;
            let span = (x1 - x0).max(0.0);
            let x_ticks = if integer_x {
                (span as usize + 1).clamp(2, 10)
            } else {
                10
            };
            let x_format = |v: &f64| {
                if integer_x {
                    format!("{}", v.round() as i64)
                } else {
                    tick_label(*v, span)
                }
            };
            chart
                .configure_mesh()
                .x_desc(x_desc)
                .y_desc(y_desc)
                .x_labels(x_ticks)
                .x_label_formatter(&x_format)
                .y_label_formatter(&|v: &f64| {
                    let t = format!("{v:.y_decimals$}");
                    if t.trim_start_matches('-')
                        .trim_matches(|c| c == '0' || c == '.')
                        .is_empty()
                    {
                        // -0.0 and the like.
                        format!("{:.y_decimals$}", 0.0)
                    } else {
                        t
                    }
                })
                .light_line_style(WHITE.mix(0.0))
                .draw()
                .map_err(|e| err(&e))?;
            for s in &panel.series {
                let c = colour(&s.name);
                if !s.spread.is_empty() {
                    chart
                        .draw_series(s.points.iter().zip(&s.spread).map(|(&(x, y), &d)| {
                            ErrorBar::new_vertical(x, (y - d).max(0.0), y, y + d, c.mix(0.6), 6)
                        }))
                        .map_err(|e| err(&e))?;
                }
                if s.paper {
                    chart
                        .draw_series(
                            s.points
                                .iter()
                                .map(|&p| Circle::new(p, 4, c.stroke_width(1))),
                        )
                        .map_err(|e| err(&e))?;
                } else {
                    let width = if ours <= 4 {
                        2 + 2 * (ours as u32 - 1 - drawn)
                    } else {
                        2
                    };
                    drawn += 1;
                    chart
                        .draw_series(
                            LineSeries::new(s.points.iter().copied(), c.stroke_width(width))
                                .point_size(3),
                        )
                        .map_err(|e| err(&e))?;
                }
            }
        }
        root.present().map_err(|e| err(&e))?;
    }
    Ok(svg)
}

/// The text of a CSV writer's buffer.
pub fn csv_text(w: csv::Writer<Vec<u8>>) -> mrpp_core::Result<String> {
    let bytes = w
        .into_inner()
        .map_err(|e| mrpp_core::Error::Internal(e.to_string()))?;
    String::from_utf8(bytes).map_err(|e| mrpp_core::Error::Internal(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn figure() -> String {
        let series = |name: &str, k: f64| Series {
            name: name.into(),
            points: (1..=4)
                .map(|i| (f64::from(i * 50), k * f64::from(i)))
                .collect(),
            ..Series::default()
        };
        line_panels(
            "Runtime",
            "agents",
            "ms",
            &[Panel {
                title: "random-32-32-20".into(),
                series: vec![series("lacam", 1.5), series("pibt", 0.5)],
            }],
        )
        .unwrap()
    }

    #[test]
    fn y_ticks_share_their_decimals_and_fractional_x_from_zero_starts_at_zero() {
        // y in 0..1.5 (the bench's runtime.svg once ticked "0, 0.50, 1, 1.50"); x from 0 to 0.05
        // (delay probabilities once started at "-0.04").
        let svg = line_panels(
            "t",
            "p",
            "ratio",
            &[Panel {
                title: "p".into(),
                series: vec![Series {
                    name: "a".into(),
                    points: vec![(0.0, 1.0), (0.01, 1.2), (0.05, 1.3)],
                    ..Series::default()
                }],
            }],
        )
        .unwrap();
        let labels: Vec<&str> = svg
            .split("<text")
            .skip(1)
            .filter_map(|t| Some(t.split('>').nth(1)?.split('<').next()?.trim()))
            .filter(|l| l.parse::<f64>().is_ok())
            .collect();
        assert!(!labels.iter().any(|l| l.starts_with('-')), "{labels:?}");
        // The y labels (one decimal each) include 0.0 and 1.0, not "0" and "1".
        assert!(
            labels.contains(&"0.0") && labels.contains(&"1.0") && labels.contains(&"1.4"),
            "{labels:?}"
        );
    }

    #[test]
    fn fractional_axes_get_short_labels_and_a_long_legend_wraps_without_repeating_colours() {
        // Ten series (like the HBMO paper's Figs. 5-6 side by side) with x in 0..0.8.
        let series: Vec<Series> = (0..10)
            .map(|k| Series {
                name: format!("a long series name {k}"),
                points: (0..5)
                    .map(|i| (f64::from(i) * 0.2, f64::from(k + i)))
                    .collect(),
                ..Series::default()
            })
            .collect();
        let svg = line_panels(
            "t",
            "swaps / robot",
            "steps",
            &[Panel {
                title: "p".into(),
                series,
            }],
        )
        .unwrap();
        // Every tick label is short: no "0.6000000000000001", none below zero.
        let labels: Vec<&str> = svg
            .split("<text")
            .skip(1)
            .filter_map(|t| Some(t.split('>').nth(1)?.split('<').next()?.trim()))
            .collect();
        // No float noise: never 5 or more decimals.
        assert!(
            labels
                .iter()
                .all(|l| l.split_once('.').is_none_or(|(_, d)| d.len() < 5)),
            "{labels:?}"
        );
        assert!(
            labels.contains(&"0.4") && !labels.iter().any(|l| l.starts_with("-0")),
            "{labels:?}"
        );
        // Entries sit in more than one row, all above the panel, each in its own colour.
        let rows: std::collections::BTreeSet<i64> = (0..10)
            .map(|k| text_ys(&svg, &format!("a long series name {k}"))[0] as i64)
            .collect();
        assert!(rows.len() > 1, "{rows:?}");
        assert!(rows.iter().all(|&y| (y as f64) < text_ys(&svg, "p")[0]));
        let colours: std::collections::BTreeSet<&str> = svg
            .split("stroke=\"")
            .skip(1)
            .filter_map(|t| t.split('"').next())
            .filter(|c| c.starts_with('#') && *c != "#000000" && *c != "#FFFFFF")
            .collect();
        assert!(colours.len() >= 10, "{colours:?}");
        assert_eq!(tick_label(0.6000000000000001, 0.8), "0.6");
        assert_eq!(tick_label(-0.0, 1.0), "0");
        assert_eq!(tick_label(1234.6, 2000.0), "1235");
    }

    /// The y coordinates of the SVG's text elements holding exactly `label`.
    fn text_ys(svg: &str, label: &str) -> Vec<f64> {
        svg.split("<text")
            .skip(1)
            .filter(|t| {
                t.split('>')
                    .nth(1)
                    .and_then(|x| x.split('<').next())
                    .is_some_and(|x| x.trim() == label)
            })
            .filter_map(|t| {
                let y = t.split(" y=\"").nth(1)?.split('"').next()?;
                y.parse().ok()
            })
            .collect()
    }

    #[test]
    fn legends_sit_above_the_panels_and_integer_axes_show_integers() {
        let svg = figure();
        // Legend entries in the band below the title, above the panel's caption.
        let caption = text_ys(&svg, "random-32-32-20")[0];
        for name in ["lacam", "pibt"] {
            let ys = text_ys(&svg, name);
            assert_eq!(ys.len(), 1, "{name}: {ys:?}");
            assert!(
                ys[0] < caption,
                "{name} at {} is not above the panel ({caption})",
                ys[0]
            );
        }
        // Agent counts as integers, never "50.0".
        assert!(!text_ys(&svg, "100").is_empty(), "no integer tick 100");
        assert!(text_ys(&svg, "100.0").is_empty() && text_ys(&svg, "50.0").is_empty());
        // Rasterised in the CLI tests (`tests/common`), with every figure the experiments and
        // the bench write.
    }
}
