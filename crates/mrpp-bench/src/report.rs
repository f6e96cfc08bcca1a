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

const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

/// Panels side by side, x = `x_desc`, y = `y_desc`. Series with the same name share a colour.
pub fn line_panels(
    title: &str,
    x_desc: &str,
    y_desc: &str,
    panels: &[Panel],
) -> Result<String, String> {
    let mut svg = String::new();
    let err = |e: &dyn std::fmt::Display| e.to_string();
    {
        let width = (420 * panels.len().max(1) as u32).max(640);
        let root = SVGBackend::with_string(&mut svg, (width, 420)).into_drawing_area();
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
        for (area, panel) in root
            .split_evenly((1, panels.len().max(1)))
            .iter()
            .zip(panels)
        {
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
            let pad = ((x1 - x0) * 0.05).max(0.5);
            let mut chart = ChartBuilder::on(area)
                .caption(&panel.title, ("sans-serif", 16))
                .margin(12)
                .x_label_area_size(32)
                .y_label_area_size(60)
                .build_cartesian_2d((x0 - pad)..(x1 + pad), 0f64..(y1 * 1.15).max(1.0))
                .map_err(|e| err(&e))?;
            chart
                .configure_mesh()
                .x_desc(x_desc)
                .y_desc(y_desc)
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
                        .map_err(|e| err(&e))?
                        .label(s.name.clone())
                        .legend(move |(x, y)| Circle::new((x + 10, y), 4, c.stroke_width(1)));
                } else {
                    chart
                        .draw_series(
                            LineSeries::new(s.points.iter().copied(), c.stroke_width(2))
                                .point_size(3),
                        )
                        .map_err(|e| err(&e))?
                        .label(s.name.clone())
                        .legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2))
                        });
                }
            }
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperLeft)
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK.mix(0.3))
                .label_font(("sans-serif", 11))
                .draw()
                .map_err(|e| err(&e))?;
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
