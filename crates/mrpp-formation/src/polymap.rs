//! Polygon maps in the CTU/CIIRC text format (the maps of the GA formation paper's §3):
//!
//! ```text
//! [SCALE]
//! 0.016            # every coordinate is multiplied by this (working units)
//! [BORDER]
//! 0 0              # the outer boundary, one "x y" vertex per line, implicitly closed
//! 2000 0
//! ...
//! [OBSTACLE]       # one block per obstacle (a hole of the free space)
//! 500 2000
//! ...
//! ```
//!
//! Accepted: any vertex order (orientation is normalised: border counter-clockwise, obstacles
//! clockwise), obstacles touching the border, decimal and signed coordinates, CRLF line ends, blank
//! lines, `#` comments (whole-line or trailing), a missing `[SCALE]` (= 1), and a polygon written
//! closed: its last vertex repeating its first, that repeated closing vertex is dropped, once,
//! before any check ([`drop_closing_vertex`]: the one ring rule, which the continuous family's
//! world reader, `mrpp_continuous::world`, applies too). Refused, each as one error naming file
//! and line: an unknown section, a non-numeric field or a wrong field count, a polygon with fewer
//! than 3 vertices (after the closing vertex is dropped), a polygon with repeated consecutive
//! vertices (a closing vertex written twice included) or zero area, a self-intersecting polygon,
//! an obstacle outside the border, a missing or second `[BORDER]`, a non-positive or non-finite
//! scale.

use std::path::Path;

use mrpp_core::error::{Error, Result, read_file};

/// A point in working units.
pub type Point = [f64; 2];

/// A simple polygon: its vertices in order (counter-clockwise for the border, clockwise for
/// obstacles after parsing), not repeating the first.
#[derive(Debug, Clone, PartialEq)]
pub struct Polygon {
    pub vertices: Vec<Point>,
    /// The file line of the polygon's section header (for messages).
    pub line: usize,
}

impl Polygon {
    /// Twice the signed area (positive = counter-clockwise).
    pub fn signed_area2(&self) -> f64 {
        let v = &self.vertices;
        (0..v.len())
            .map(|i| {
                let (a, b) = (v[i], v[(i + 1) % v.len()]);
                a[0] * b[1] - b[0] * a[1]
            })
            .sum()
    }

    /// The edges `(a, b)` in order, closing the polygon.
    pub fn edges(&self) -> impl Iterator<Item = (Point, Point)> + '_ {
        let v = &self.vertices;
        (0..v.len()).map(move |i| (v[i], v[(i + 1) % v.len()]))
    }

    /// Whether `p` lies strictly inside (ray casting; points on the boundary may go either way).
    pub fn contains(&self, p: Point) -> bool {
        let mut inside = false;
        for (a, b) in self.edges() {
            if (a[1] > p[1]) != (b[1] > p[1]) {
                let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
                if p[0] < x {
                    inside = !inside;
                }
            }
        }
        inside
    }
}

/// A polygon map: the border and the obstacles, in working units (scale applied).
#[derive(Debug, Clone, PartialEq)]
pub struct PolygonMap {
    pub scale: f64,
    pub border: Polygon,
    pub obstacles: Vec<Polygon>,
}

impl PolygonMap {
    /// Reads a map file.
    pub fn load(path: &Path) -> Result<Self> {
        let text = read_file(path)?;
        Self::parse(&text, path)
    }

    /// Parses map text; `path` only names the source in errors.
    pub fn parse(text: &str, path: &Path) -> Result<Self> {
        let (scale, sections) = sections(text, path)?;
        let mut border: Option<Polygon> = None;
        let mut obstacles = Vec::new();
        for (kind, mut poly) in sections {
            drop_closing_vertex(&mut poly.vertices);
            for v in &mut poly.vertices {
                *v = [v[0] * scale, v[1] * scale];
            }
            check_polygon(&poly, path)?;
            if kind == Kind::Border {
                if border.is_some() {
                    return Err(Error::parse(path, poly.line, "a second [BORDER]"));
                }
                border = Some(oriented(poly, true));
            } else {
                obstacles.push(oriented(poly, false));
            }
        }
        let border = border.ok_or_else(|| Error::invalid(path, "no [BORDER] section"))?;
        for o in &obstacles {
            if let Some(v) = o.vertices.iter().find(|v| !inside_or_on(&border, **v)) {
                return Err(Error::parse(
                    path,
                    o.line,
                    format!(
                        "obstacle vertex ({}, {}) is outside the border",
                        v[0] / scale,
                        v[1] / scale
                    ),
                ));
            }
        }
        Ok(PolygonMap {
            scale,
            border,
            obstacles,
        })
    }

    /// Whether `p` is in the free space: inside the border and inside no obstacle.
    pub fn is_free(&self, p: Point) -> bool {
        self.border.contains(p) && !self.obstacles.iter().any(|o| o.contains(p))
    }

    /// Every polygon, the border first (index 0), then the obstacles.
    pub fn polygons(&self) -> impl Iterator<Item = &Polygon> {
        std::iter::once(&self.border).chain(&self.obstacles)
    }

    /// The distance from `p` to the nearest boundary (border or obstacle edge).
    pub fn clearance(&self, p: Point) -> f64 {
        self.polygons()
            .flat_map(|poly| poly.edges())
            .map(|(a, b)| point_segment_distance(p, a, b))
            .fold(f64::INFINITY, f64::min)
    }

    /// Whether the segment `a`–`b` crosses or touches any boundary edge.
    pub fn segment_hits_boundary(&self, a: Point, b: Point) -> bool {
        self.polygons()
            .flat_map(|poly| poly.edges())
            .any(|(c, d)| segments_intersect(a, b, c, d))
    }

    /// Bounding box `(min, max)` of the border.
    pub fn bounds(&self) -> (Point, Point) {
        let v = &self.border.vertices;
        let min = v
            .iter()
            .fold([f64::INFINITY; 2], |m, p| [m[0].min(p[0]), m[1].min(p[1])]);
        let max = v.iter().fold([f64::NEG_INFINITY; 2], |m, p| {
            [m[0].max(p[0]), m[1].max(p[1])]
        });
        (min, max)
    }

    /// The map in the CTU text format, in file units (scale undone).
    pub fn to_text(&self) -> String {
        let mut s = format!("[SCALE]\n{}\n", self.scale);
        let mut block = |tag: &str, p: &Polygon| {
            s.push_str(&format!("\n[{tag}]\n"));
            for v in &p.vertices {
                s.push_str(&format!("{} {}\n", v[0] / self.scale, v[1] / self.scale));
            }
        };
        block("BORDER", &self.border);
        for o in &self.obstacles {
            block("OBSTACLE", o);
        }
        s
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Border,
    Obstacle,
}

/// Splits the text into its scale and polygon sections (vertices unscaled).
fn sections(text: &str, path: &Path) -> Result<(f64, Vec<(Kind, Polygon)>)> {
    // A grid map given where a polygon map belongs (`gen formation --map room.map`): say so,
    // rather than that `type` is not a number.
    let first = text.lines().find(|l| !l.trim().is_empty()).unwrap_or("");
    if first.trim_start().starts_with("type ") {
        return Err(Error::parse(
            path,
            1,
            "this is a MovingAI grid map; formations need a polygon map ([SCALE], [BORDER] and \
             [OBSTACLE] sections of x y vertices; e.g. data/polygon-maps/gaps.txt)",
        ));
    }
    let mut scale: Option<f64> = None;
    let mut in_scale = false;
    let mut out: Vec<(Kind, Polygon)> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let no = i + 1;
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        if line.starts_with('[') {
            in_scale = false;
            match line.to_ascii_uppercase().as_str() {
                "[SCALE]" => in_scale = true,
                "[BORDER]" => out.push((
                    Kind::Border,
                    Polygon {
                        vertices: Vec::new(),
                        line: no,
                    },
                )),
                "[OBSTACLE]" => out.push((
                    Kind::Obstacle,
                    Polygon {
                        vertices: Vec::new(),
                        line: no,
                    },
                )),
                other => {
                    return Err(Error::parse(
                        path,
                        no,
                        format!("unknown section {other} (known: [SCALE], [BORDER], [OBSTACLE])"),
                    ));
                }
            }
            continue;
        }
        let nums = numbers(line, path, no)?;
        if in_scale {
            match (nums.as_slice(), scale) {
                ([s], None) if s.is_finite() && *s > 0.0 => scale = Some(*s),
                ([s], None) => {
                    return Err(Error::parse(
                        path,
                        no,
                        format!("scale must be positive, got {s}"),
                    ));
                }
                _ => return Err(Error::parse(path, no, "[SCALE] holds exactly one number")),
            }
            continue;
        }
        let Some((_, poly)) = out.last_mut() else {
            return Err(Error::parse(
                path,
                no,
                "a vertex before any [BORDER] or [OBSTACLE] section",
            ));
        };
        match nums.as_slice() {
            [x, y] => poly.vertices.push([*x, *y]),
            _ => {
                return Err(Error::parse(
                    path,
                    no,
                    format!("expected `x y`, found `{line}`"),
                ));
            }
        }
    }
    Ok((scale.unwrap_or(1.0), out))
}

fn numbers(line: &str, path: &Path, no: usize) -> Result<Vec<f64>> {
    line.split_whitespace()
        .map(|f| {
            f.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| Error::parse(path, no, format!("`{f}` is not a number")))
        })
        .collect()
}

/// The one ring rule for polygons: a ring whose last vertex repeats its first (written closed)
/// is the ring without that repeat, so `[a, b, c, a]` is the triangle `[a, b, c]` and `[a, b, a]`
/// the two vertices `[a, b]` (which the checks then refuse as too few). Only one closing vertex
/// is dropped: a ring that still repeats its first vertex after that is left for the checks.
/// Returns whether a vertex was dropped.
///
/// The continuous family's world reader (`mrpp_continuous::world::drop_closing_vertex`) holds a
/// copy of these three lines, tested alike: the two families share no crate but `mrpp-core`,
/// which has no geometry.
pub fn drop_closing_vertex(ring: &mut Vec<Point>) -> bool {
    let closed = ring.len() >= 2 && ring.first() == ring.last();
    if closed {
        ring.pop();
    }
    closed
}

/// At least 3 distinct consecutive vertices, non-zero area, no self-intersection.
fn check_polygon(p: &Polygon, path: &Path) -> Result<()> {
    let n = p.vertices.len();
    if n < 3 {
        return Err(Error::parse(
            path,
            p.line,
            format!("a polygon needs at least 3 vertices, this one has {n}"),
        ));
    }
    let v = &p.vertices;
    if let Some(i) = (0..n).find(|&i| v[i] == v[(i + 1) % n]) {
        return Err(Error::parse(
            path,
            p.line,
            format!(
                "vertices {} and {} coincide: consecutive vertices must differ (a closing \
                 vertex repeating the first is written at most once)",
                i + 1,
                (i + 1) % n + 1
            ),
        ));
    }
    for i in 0..n {
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue;
            }
            let (a, b, c, d) = (v[i], v[(i + 1) % n], v[j], v[(j + 1) % n]);
            if segments_intersect(a, b, c, d) {
                return Err(Error::parse(
                    path,
                    p.line,
                    format!(
                        "the polygon intersects itself (edges {} and {})",
                        i + 1,
                        j + 1
                    ),
                ));
            }
        }
    }
    if p.signed_area2().abs() < 1e-12 {
        return Err(Error::parse(path, p.line, "the polygon has zero area"));
    }
    Ok(())
}

/// The polygon with counter-clockwise (`ccw`) or clockwise vertex order.
fn oriented(mut p: Polygon, ccw: bool) -> Polygon {
    if (p.signed_area2() > 0.0) != ccw {
        p.vertices.reverse();
    }
    p
}

/// Inside, or on an edge (within a tolerance).
fn inside_or_on(poly: &Polygon, p: Point) -> bool {
    poly.contains(p)
        || poly
            .edges()
            .any(|(a, b)| point_segment_distance(p, a, b) < 1e-9)
}

/// Euclidean distance from `p` to the segment `a`–`b`.
pub fn point_segment_distance(p: Point, a: Point, b: Point) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let t = if len2 == 0.0 {
        0.0
    } else {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
    };
    let (qx, qy) = (a[0] + t * dx, a[1] + t * dy);
    ((p[0] - qx).powi(2) + (p[1] - qy).powi(2)).sqrt()
}

fn orient(a: Point, b: Point, c: Point) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

fn on_segment(a: Point, b: Point, p: Point) -> bool {
    p[0] >= a[0].min(b[0]) - 1e-12
        && p[0] <= a[0].max(b[0]) + 1e-12
        && p[1] >= a[1].min(b[1]) - 1e-12
        && p[1] <= a[1].max(b[1]) + 1e-12
}

/// Whether the closed segments `a`–`b` and `c`–`d` share a point.
pub fn segments_intersect(a: Point, b: Point, c: Point, d: Point) -> bool {
    let (d1, d2, d3, d4) = (
        orient(c, d, a),
        orient(c, d, b),
        orient(a, b, c),
        orient(a, b, d),
    );
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    (d1 == 0.0 && on_segment(c, d, a))
        || (d2 == 0.0 && on_segment(c, d, b))
        || (d3 == 0.0 && on_segment(a, b, c))
        || (d4 == 0.0 && on_segment(a, b, d))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<PolygonMap> {
        PolygonMap::parse(text, Path::new("m.txt"))
    }

    #[test]
    fn the_format_with_its_liberties() {
        let m = parse("# a map\r\n[SCALE]\r\n0.5\r\n\r\n[BORDER]\r\n0 0\r\n0 10\r\n10 10\r\n10 0\r\n[OBSTACLE]\r\n2 2 # ccw\r\n4 2\r\n4 4\r\n2 4\r\n[obstacle]\n6 0\n8 0\n8 3\n").unwrap();
        assert_eq!(m.scale, 0.5);
        assert!(m.border.signed_area2() > 0.0);
        assert!(m.obstacles.iter().all(|o| o.signed_area2() < 0.0));
        assert_eq!(m.border.vertices.len(), 4);
        assert!(m.is_free([0.5, 4.0]) && !m.is_free([1.5, 1.5]) && !m.is_free([3.5, 0.5]));
        assert!(!m.is_free([6.0, 1.0]));
        assert!((m.clearance([1.5, 2.5]) - 0.5).abs() < 1e-12);
        let again = parse(&m.to_text()).unwrap();
        let shape = |m: &PolygonMap| -> Vec<Vec<Point>> {
            m.polygons().map(|p| p.vertices.clone()).collect()
        };
        assert_eq!(shape(&again), shape(&m));
    }

    /// Issue 27 C: the one ring rule, as in the continuous world reader: a polygon written
    /// closed is the open one (it used to be refused: "not closed properly").
    #[test]
    fn a_repeated_closing_vertex_is_dropped_once() {
        let (a, b, c) = ([0.0, 0.0], [1.0, 0.0], [0.0, 1.0]);
        let mut ring = vec![a, b, c, a];
        assert!(drop_closing_vertex(&mut ring));
        assert_eq!(ring, vec![a, b, c]);
        assert!(!drop_closing_vertex(&mut ring));
        let mut twice = vec![a, b, c, a, a];
        assert!(drop_closing_vertex(&mut twice));
        assert_eq!(twice, vec![a, b, c, a]);
        let mut short = vec![a, b, a];
        drop_closing_vertex(&mut short);
        assert_eq!(short, vec![a, b]);
        let mut empty: Vec<Point> = Vec::new();
        assert!(!drop_closing_vertex(&mut empty));

        let open = parse("[BORDER]\n0 0\n10 0\n10 10\n0 10\n[OBSTACLE]\n2 2\n4 2\n3 4\n").unwrap();
        let closed =
            parse("[BORDER]\n0 0\n10 0\n10 10\n0 10\n0 0\n[OBSTACLE]\n2 2\n4 2\n3 4\n2 2\n")
                .unwrap();
        let shape = |m: &PolygonMap| -> Vec<Vec<Point>> {
            m.polygons().map(|p| p.vertices.clone()).collect()
        };
        assert_eq!(shape(&closed), shape(&open));
        assert_eq!(closed.border.vertices.len(), 4);
        assert_eq!(closed.obstacles[0].vertices.len(), 3);
        // Two distinct vertices written closed are too few; a closing vertex written twice
        // leaves a repeated pair.
        let border = "[BORDER]\n0 0\n10 0\n10 10\n0 10\n";
        let e = parse(&format!("{border}[OBSTACLE]\n2 2\n4 2\n2 2\n"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("m.txt:6:") && e.contains("at least 3 vertices, this one has 2"),
            "{e}"
        );
        let e = parse(&format!("{border}[OBSTACLE]\n2 2\n4 2\n3 4\n2 2\n2 2\n"))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("m.txt:6:") && e.contains("coincide"), "{e}");
    }

    #[test]
    fn every_bad_case_names_its_line() {
        let border = "[BORDER]\n0 0\n10 0\n10 10\n0 10\n";
        let cases = [
            (
                format!("{border}[OBSTACLE]\n1 1\n2 2\n"),
                "m.txt:6:",
                "at least 3",
            ),
            (
                format!("{border}[OBSTACLE]\n1 1\n3 1\n1 3\n3 3\n"),
                "m.txt:6:",
                "intersects itself",
            ),
            (
                format!("{border}[OBSTACLE]\n1 1\n1 1\n3 3\n"),
                "m.txt:6:",
                "coincide",
            ),
            (
                format!("{border}[OBSTACLE]\n1 1\n2 2\n3 3\n"),
                "m.txt:6:",
                "zero area",
            ),
            (
                format!("{border}[OBSTACLE]\n1 1\n20 1\n1 3\n"),
                "m.txt:6:",
                "outside the border",
            ),
            (
                format!("{border}[HOLE]\n1 1\n"),
                "m.txt:6:",
                "unknown section",
            ),
            (
                format!("{border}[OBSTACLE]\n1 x\n"),
                "m.txt:7:",
                "not a number",
            ),
            (
                format!("{border}[OBSTACLE]\n1 2 3\n"),
                "m.txt:7:",
                "expected `x y`",
            ),
            ("[SCALE]\n-1\n".to_string(), "m.txt:2:", "positive"),
            ("1 2\n".to_string(), "m.txt:1:", "before any"),
            (format!("{border}{border}"), "m.txt:6:", "second [BORDER]"),
        ];
        for (text, prefix, needle) in cases {
            let e = parse(&text).unwrap_err().to_string();
            assert!(e.starts_with(prefix) && e.contains(needle), "{e}");
        }
        let e = parse("[OBSTACLE]\n1 1\n2 1\n2 2\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("no [BORDER]"), "{e}");
    }
}
