//! Plane geometry for discs among polygons: distances between points, segments and polygons, and
//! the closest approach of two discs moving linearly over one step (swept discs). Everything is
//! in world units; polygons are closed vertex rings in any orientation, convex or not.

/// A point `[x, y]`.
pub type Point = [f64; 2];

/// `a + b`.
pub fn add(a: Point, b: Point) -> Point {
    [a[0] + b[0], a[1] + b[1]]
}

/// `a − b`.
pub fn sub(a: Point, b: Point) -> Point {
    [a[0] - b[0], a[1] - b[1]]
}

/// The dot product.
pub fn dot(a: Point, b: Point) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// The z component of the cross product.
pub fn cross(a: Point, b: Point) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// Euclidean length of `a`.
pub fn norm(a: Point) -> f64 {
    (a[0] * a[0] + a[1] * a[1]).sqrt()
}

/// Euclidean distance.
pub fn dist(a: Point, b: Point) -> f64 {
    norm(sub(a, b))
}

/// Distance from `p` to the segment `a`–`b`.
pub fn point_segment(p: Point, a: Point, b: Point) -> f64 {
    let ab = sub(b, a);
    let len2 = dot(ab, ab);
    let t = if len2 > 0.0 {
        (dot(sub(p, a), ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    dist(p, [a[0] + t * ab[0], a[1] + t * ab[1]])
}

/// Whether the closed segments `a`–`b` and `c`–`d` meet.
pub fn segments_cross(a: Point, b: Point, c: Point, d: Point) -> bool {
    let (d1, d2) = (cross(sub(b, a), sub(c, a)), cross(sub(b, a), sub(d, a)));
    let (d3, d4) = (cross(sub(d, c), sub(a, c)), cross(sub(d, c), sub(b, c)));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    let on = |p: Point, q: Point, r: Point| point_segment(r, p, q) == 0.0;
    on(a, b, c) || on(a, b, d) || on(c, d, a) || on(c, d, b)
}

/// Distance between the segments `a`–`b` and `c`–`d` (0 when they meet).
pub fn segment_segment(a: Point, b: Point, c: Point, d: Point) -> f64 {
    if segments_cross(a, b, c, d) {
        return 0.0;
    }
    point_segment(a, c, d)
        .min(point_segment(b, c, d))
        .min(point_segment(c, a, b))
        .min(point_segment(d, a, b))
}

/// Whether `p` lies strictly inside the polygon (even–odd rule; points on the boundary may go
/// either way, callers measure the boundary distance separately).
pub fn inside(p: Point, poly: &[Point]) -> bool {
    let mut c = false;
    let n = poly.len();
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
            if p[0] < x {
                c = !c;
            }
        }
    }
    c
}

/// The polygon's edges as vertex pairs.
pub fn edges(poly: &[Point]) -> impl Iterator<Item = (Point, Point)> + '_ {
    (0..poly.len()).map(move |i| (poly[i], poly[(i + 1) % poly.len()]))
}

/// The polygon's bounding box `[x_min, y_min, x_max, y_max]`.
pub fn bounding_box(poly: &[Point]) -> [f64; 4] {
    poly.iter().fold(
        [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ],
        |b, v| {
            [
                b[0].min(v[0]),
                b[1].min(v[1]),
                b[2].max(v[0]),
                b[3].max(v[1]),
            ]
        },
    )
}

/// The distance from `p` to the box `[x_min, y_min, x_max, y_max]` (0 inside): a lower bound on
/// its distance to anything in the box.
pub fn box_distance(p: Point, b: &[f64; 4]) -> f64 {
    let dx = (b[0] - p[0]).max(p[0] - b[2]).max(0.0);
    let dy = (b[1] - p[1]).max(p[1] - b[3]).max(0.0);
    (dx * dx + dy * dy).sqrt()
}

/// Distance from `p` to the polygon (0 inside).
pub fn point_polygon(p: Point, poly: &[Point]) -> f64 {
    if inside(p, poly) {
        return 0.0;
    }
    edges(poly)
        .map(|(a, b)| point_segment(p, a, b))
        .fold(f64::INFINITY, f64::min)
}

/// Distance from the segment `a`–`b` to the polygon (0 when it enters it): the clearance of a
/// disc centre sweeping that segment.
pub fn segment_polygon(a: Point, b: Point, poly: &[Point]) -> f64 {
    if inside(a, poly) || inside(b, poly) {
        return 0.0;
    }
    edges(poly)
        .map(|(c, d)| segment_segment(a, b, c, d))
        .fold(f64::INFINITY, f64::min)
}

/// The least distance between two points moving linearly over one step, `p` from `p0` to `p1`
/// and `q` from `q0` to `q1` (same start and end times): the closest approach of two swept discs'
/// centres.
pub fn closest_approach(p0: Point, p1: Point, q0: Point, q1: Point) -> f64 {
    // Relative position r(t) = (p0 − q0) + t ((p1 − p0) − (q1 − q0)), t in [0, 1]: the distance
    // from the origin to the segment r(0)–r(1).
    let r0 = sub(p0, q0);
    let r1 = sub(p1, q1);
    point_segment([0.0, 0.0], r0, r1)
}

/// Twice the signed area (positive counter-clockwise).
pub fn signed_area2(poly: &[Point]) -> f64 {
    edges(poly).map(|(a, b)| cross(a, b)).sum()
}

/// Whether two non-adjacent edges of the ring meet (a self-intersecting polygon).
pub fn self_intersects(poly: &[Point]) -> bool {
    let n = poly.len();
    for i in 0..n {
        for j in i + 1..n {
            let adjacent = j == i + 1 || (i == 0 && j == n - 1);
            if adjacent {
                continue;
            }
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            let (c, d) = (poly[j], poly[(j + 1) % n]);
            if segments_cross(a, b, c, d) {
                return true;
            }
        }
    }
    false
}

/// Points bucketed in square cells over a box, to find the points near a point without looking
/// at all of them.
#[derive(Debug, Clone)]
pub struct PointGrid {
    origin: Point,
    cell: f64,
    cols: usize,
    rows: usize,
    cells: Vec<Vec<usize>>,
}

impl PointGrid {
    /// Buckets `points` (all inside `bounds` = `[x_min, y_min, x_max, y_max]`) in cells of side
    /// `cell` (> 0).
    pub fn new(points: &[Point], bounds: [f64; 4], cell: f64) -> Self {
        // At most about four cells per point: a huge workspace gets coarser cells, not more.
        let area = (bounds[2] - bounds[0]) * (bounds[3] - bounds[1]);
        let cell = cell
            .max((area / (4.0 * points.len().max(1) as f64)).sqrt())
            .max(1e-9);
        let cols = (((bounds[2] - bounds[0]) / cell).ceil() as usize).clamp(1, 4096);
        let rows = (((bounds[3] - bounds[1]) / cell).ceil() as usize).clamp(1, 4096);
        let mut g = PointGrid {
            origin: [bounds[0], bounds[1]],
            cell,
            cols,
            rows,
            cells: vec![Vec::new(); cols * rows],
        };
        for (i, &p) in points.iter().enumerate() {
            let (c, r) = g.index(p);
            g.cells[r * cols + c].push(i);
        }
        g
    }

    fn index(&self, p: Point) -> (usize, usize) {
        let c = ((p[0] - self.origin[0]) / self.cell).floor().max(0.0) as usize;
        let r = ((p[1] - self.origin[1]) / self.cell).floor().max(0.0) as usize;
        (c.min(self.cols - 1), r.min(self.rows - 1))
    }

    /// The indices of the points in the cells that a disc of `radius` around `p` overlaps (a
    /// superset of the points within `radius`), in cell order.
    pub fn near(&self, p: Point, radius: f64) -> impl Iterator<Item = usize> + '_ {
        let (c0, r0) = self.index([p[0] - radius, p[1] - radius]);
        let (c1, r1) = self.index([p[0] + radius, p[1] + radius]);
        (r0..=r1).flat_map(move |r| {
            (c0..=c1).flat_map(move |c| self.cells[r * self.cols + c].iter().copied())
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SQUARE: [Point; 4] = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];

    #[test]
    fn distances() {
        assert_eq!(point_segment([1.0, 1.0], [0.0, 0.0], [2.0, 0.0]), 1.0);
        assert_eq!(point_segment([3.0, 0.0], [0.0, 0.0], [2.0, 0.0]), 1.0);
        assert_eq!(point_polygon([1.0, 1.0], &SQUARE), 0.0);
        assert_eq!(point_polygon([3.0, 1.0], &SQUARE), 1.0);
        assert_eq!(segment_polygon([-1.0, 1.0], [3.0, 1.0], &SQUARE), 0.0);
        assert_eq!(segment_polygon([-1.0, 3.0], [3.0, 3.0], &SQUARE), 1.0);
        assert!(segments_cross(
            [0.0, 0.0],
            [1.0, 1.0],
            [0.0, 1.0],
            [1.0, 0.0]
        ));
        assert!(!self_intersects(&SQUARE));
        assert!(self_intersects(&[
            [0.0, 0.0],
            [2.0, 2.0],
            [2.0, 0.0],
            [0.0, 2.0]
        ]));
    }

    #[test]
    fn swept_discs_meet_mid_step() {
        // Head-on: both end 4 apart but pass through each other.
        let d = closest_approach([0.0, 0.0], [4.0, 0.0], [4.0, 0.0], [0.0, 0.0]);
        assert_eq!(d, 0.0);
        // Parallel moves keep their distance.
        let d = closest_approach([0.0, 0.0], [4.0, 0.0], [0.0, 3.0], [4.0, 3.0]);
        assert_eq!(d, 3.0);
    }
}
