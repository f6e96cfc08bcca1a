//! 4-connected grid maps: MovingAI `.map` files and the H* paper's ASCII maps, detected by content.
//!
//! Cell `(x, y)` is column `x`, row `y`, both from 0 at the top-left. Every free cell becomes a
//! vertex of a [`Graph`]; neighbours are listed in the fixed order up, right, down, left, which is
//! the tie-break order planners inherit.

use std::path::Path;
use std::sync::Arc;

use mrpp_core::error::{Error, Result, read_file};
use mrpp_core::mapf::graph::{Graph, VertexId};

const NO_VERTEX: u32 = u32::MAX;

/// A grid map and its graph of free cells.
#[derive(Debug, Clone)]
pub struct GridMap {
    width: u32,
    height: u32,
    free: Vec<bool>,
    vertex_of: Vec<u32>,
    graph: Arc<Graph>,
}

/// Which text format a map file was read from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MapFormat {
    /// MovingAI: a `type`, `height`, `width` header (any order; `type` optional), `map`, then rows
    /// of MovingAI's terrain characters: `.`, `G` and `S` (swamp) are free; `@`, `O`, `T` (trees)
    /// and `W` (water, which cannot be entered from land) are walls. The League of Robot Runners'
    /// `E` (emitter) is free too (the League of Robot Runners' maps).
    MovingAi,
    /// H* paper: rows of `#` (wall) and space (free); CRLF and a missing final newline tolerated.
    Ascii,
}

impl GridMap {
    /// Builds a map from rows of free (`true`) / blocked cells. Rows may differ in length; missing
    /// cells at a row's end count as blocked here (callers decide padding).
    pub fn from_free_rows(rows: &[Vec<bool>]) -> Self {
        let height = rows.len() as u32;
        let width = rows.iter().map(Vec::len).max().unwrap_or(0) as u32;
        let mut free = vec![false; (width * height) as usize];
        for (y, row) in rows.iter().enumerate() {
            for (x, &f) in row.iter().enumerate() {
                free[y * width as usize + x] = f;
            }
        }
        let mut vertex_of = vec![NO_VERTEX; free.len()];
        let mut coords = Vec::new();
        for y in 0..height {
            for x in 0..width {
                let i = (y * width + x) as usize;
                if free[i] {
                    vertex_of[i] = coords.len() as u32;
                    coords.push((x, y));
                }
            }
        }
        let at = |x: i64, y: i64| -> Option<VertexId> {
            if x < 0 || y < 0 || x >= width as i64 || y >= height as i64 {
                return None;
            }
            let v = vertex_of[(y as u32 * width + x as u32) as usize];
            (v != NO_VERTEX).then_some(v)
        };
        // Compressed rows straight away (no list per vertex: a million-cell map loads in tens of
        // milliseconds).
        let mut offsets = Vec::with_capacity(coords.len() + 1);
        let mut targets = Vec::with_capacity(coords.len() * 4);
        offsets.push(0u32);
        for &(x, y) in &coords {
            let (x, y) = (x as i64, y as i64);
            targets.extend(
                [(x, y - 1), (x + 1, y), (x, y + 1), (x - 1, y)]
                    .into_iter()
                    .filter_map(|(nx, ny)| at(nx, ny)),
            );
            offsets.push(targets.len() as u32);
        }
        let graph = Arc::new(Graph::from_csr(offsets, targets, Some(coords)));
        GridMap {
            width,
            height,
            free,
            vertex_of,
            graph,
        }
    }

    /// Parses map text; `path` only names the source in errors.
    pub fn parse(text: &str, path: &Path) -> Result<(Self, MapFormat)> {
        // MovingAI: a header of `type`, `height`, `width` in any order (the visualizer's own
        // examples have no `type` line), then `map`.
        let first = text.lines().find(|l| !l.trim().is_empty()).unwrap_or("");
        let word = first.split_whitespace().next().unwrap_or("");
        let number = first
            .split_whitespace()
            .nth(1)
            .is_some_and(|v| v.parse::<u32>().is_ok());
        if word == "type" || (matches!(word, "height" | "width") && number) {
            Ok((parse_movingai(text, path)?, MapFormat::MovingAi))
        } else {
            Ok((parse_ascii(text, path)?, MapFormat::Ascii))
        }
    }

    /// The map as MovingAI text (`type octile`, `height`, `width`, `map`, then rows of `.` for
    /// free cells and `@` for walls), which [`GridMap::parse`] reads back to the same map and any
    /// MovingAI tool reads (`mrpp convert`).
    pub fn movingai_text(&self) -> String {
        let mut s = format!(
            "type octile\nheight {}\nwidth {}\nmap\n",
            self.height, self.width
        );
        s.reserve(((self.width + 1) * self.height) as usize);
        for y in 0..self.height {
            for x in 0..self.width {
                s.push(if self.is_free(x, y) { '.' } else { '@' });
            }
            s.push('\n');
        }
        s
    }

    /// Reads a map file in either format.
    pub fn load(path: &Path) -> Result<Self> {
        let text = read_file(path)?;
        Ok(Self::parse(&text, path)?.0)
    }

    pub fn width(&self) -> u32 {
        self.width
    }
    pub fn height(&self) -> u32 {
        self.height
    }
    pub fn graph(&self) -> &Graph {
        &self.graph
    }
    /// The graph, shared (what a [`mrpp_core::MapfProblem`] holds).
    pub fn graph_arc(&self) -> &Arc<Graph> {
        &self.graph
    }
    pub fn is_free(&self, x: u32, y: u32) -> bool {
        x < self.width && y < self.height && self.free[(y * self.width + x) as usize]
    }
    /// The vertex of a free cell, `None` for walls and cells off the map.
    pub fn vertex_at(&self, x: i64, y: i64) -> Option<VertexId> {
        if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 {
            return None;
        }
        let v = self.vertex_of[(y as u32 * self.width + x as u32) as usize];
        (v != NO_VERTEX).then_some(v)
    }
    /// The cell of a vertex.
    pub fn cell(&self, v: VertexId) -> (u32, u32) {
        self.graph.coord(v).expect("grid graphs carry coordinates")
    }
    /// Why `(x, y)` cannot hold a robot, or `None` when it can.
    pub fn cell_problem(&self, x: i64, y: i64) -> Option<String> {
        if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 {
            Some(format!(
                "cell ({x},{y}) is off the {}x{} map",
                self.width, self.height
            ))
        } else if self.vertex_at(x, y).is_none() {
            Some(format!("cell ({x},{y}) is a wall"))
        } else {
            None
        }
    }
}

fn parse_movingai(text: &str, path: &Path) -> Result<GridMap> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim_end_matches('\r')));
    let mut height = None;
    let mut width = None;
    let mut last_line = 0;
    loop {
        let Some((no, line)) = lines.next() else {
            return Err(Error::parse(
                path,
                last_line + 1,
                "truncated header: no `map` line",
            ));
        };
        last_line = no;
        let mut parts = line.split_whitespace();
        match (parts.next(), parts.next()) {
            (Some("type"), _) => {}
            (Some("height"), Some(v)) => {
                height = Some(
                    v.parse::<u32>()
                        .map_err(|_| Error::parse(path, no, format!("bad height `{v}`")))?,
                )
            }
            (Some("width"), Some(v)) => {
                width = Some(
                    v.parse::<u32>()
                        .map_err(|_| Error::parse(path, no, format!("bad width `{v}`")))?,
                )
            }
            (Some("map"), None) => break,
            (None, _) => {}
            _ => {
                return Err(Error::parse(
                    path,
                    no,
                    format!("unexpected header line `{line}`"),
                ));
            }
        }
    }
    let height = height.ok_or_else(|| Error::parse(path, last_line, "header has no `height`"))?;
    let width = width.ok_or_else(|| Error::parse(path, last_line, "header has no `width`"))?;
    if width == 0 || height == 0 || (width as u64) * (height as u64) > 100_000_000 {
        return Err(Error::parse(
            path,
            last_line,
            format!("unusable map size {width}x{height}"),
        ));
    }
    let mut rows = Vec::with_capacity(height as usize);
    for _ in 0..height {
        let Some((no, line)) = lines.next() else {
            return Err(Error::parse(
                path,
                last_line + 1,
                format!("truncated map: {} of {height} rows", rows.len()),
            ));
        };
        last_line = no;
        if line.chars().count() != width as usize {
            return Err(Error::parse(
                path,
                no,
                format!("row has {} cells, expected {width}", line.chars().count()),
            ));
        }
        let mut row = Vec::with_capacity(width as usize);
        for (x, ch) in line.chars().enumerate() {
            row.push(match ch {
                '.' | 'G' | 'S' | 'E' => true,
                '@' | 'O' | 'T' | 'W' => false,
                other => {
                    return Err(Error::parse(
                        path,
                        no,
                        format!("unknown map character `{other}` in column {x}"),
                    ));
                }
            });
        }
        rows.push(row);
    }
    if let Some((no, line)) = lines.find(|(_, l)| !l.trim().is_empty()) {
        return Err(Error::parse(
            path,
            no,
            format!("text after the last map row: `{line}`"),
        ));
    }
    finish(GridMap::from_free_rows(&rows), path)
}

fn parse_ascii(text: &str, path: &Path) -> Result<GridMap> {
    let mut rows: Vec<Vec<bool>> = Vec::new();
    for (i, line) in text.split('\n').enumerate() {
        let line = line.strip_suffix('\r').unwrap_or(line);
        let mut row = Vec::with_capacity(line.len());
        for (x, ch) in line.chars().enumerate() {
            row.push(match ch {
                '#' => false,
                ' ' | '.' => true,
                other => {
                    return Err(Error::parse(
                        path,
                        i + 1,
                        format!(
                            "not a MovingAI map (it starts without a `type`, `height` or \
                             `width` header line) and not an H* paper map: unexpected \
                             character `{}` in column {x} (that format has `#` for walls and \
                             spaces for free cells)",
                            other.escape_debug()
                        ),
                    ));
                }
            });
        }
        rows.push(row);
    }
    while rows.last().is_some_and(Vec::is_empty) {
        rows.pop();
    }
    if rows.is_empty() {
        return Err(Error::invalid(path, "empty map"));
    }
    // A row shorter than the longest counts as free beyond its end (the format's convention).
    let width = rows.iter().map(Vec::len).max().unwrap_or(0);
    for row in &mut rows {
        row.resize(width, true);
    }
    finish(GridMap::from_free_rows(&rows), path)
}

fn finish(map: GridMap, path: &Path) -> Result<GridMap> {
    if map.graph.num_vertices() == 0 {
        return Err(Error::invalid(path, "map has no free cell"));
    }
    Ok(map)
}

/// The free cells of the map's largest connected area (the first found among equals), in
/// breadth-first order from its lowest vertex.
pub fn largest_component(map: &GridMap) -> Vec<VertexId> {
    let g = map.graph();
    let mut component = vec![usize::MAX; g.num_vertices()];
    let mut best: Vec<VertexId> = Vec::new();
    for s in 0..g.num_vertices() {
        if component[s] != usize::MAX {
            continue;
        }
        component[s] = s;
        let mut cells = vec![s as VertexId];
        let mut k = 0;
        while k < cells.len() {
            for &w in g.neighbors(cells[k]) {
                if component[w as usize] == usize::MAX {
                    component[w as usize] = s;
                    cells.push(w);
                }
            }
            k += 1;
        }
        if cells.len() > best.len() {
            best = cells;
        }
    }
    best
}

/// A random instance of `agents` agents on `map` (what `mrpp gen scen` writes): starts distinct,
/// goals distinct, all drawn uniformly (seeded) from the largest connected component, so every
/// agent can reach its goal.
///
/// # Errors
/// A message when the component has fewer than `agents` cells or `agents` is 0.
pub fn random_instance(
    map: &GridMap,
    agents: usize,
    seed: u64,
) -> std::result::Result<mrpp_core::Instance, String> {
    use rand::SeedableRng;
    use rand::seq::IndexedRandom;
    let best = largest_component(map);
    if agents == 0 || agents > best.len() {
        return Err(format!(
            "cannot place {agents} agents: the largest connected area has {} free cells",
            best.len()
        ));
    }
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let starts: Vec<VertexId> = best.sample(&mut rng, agents).copied().collect();
    let goals: Vec<VertexId> = best.sample(&mut rng, agents).copied().collect();
    mrpp_core::Instance::new(starts, goals)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p() -> &'static Path {
        Path::new("test.map")
    }

    #[test]
    fn movingai_map_parses() {
        let (m, f) =
            GridMap::parse("type octile\nheight 2\nwidth 3\nmap\n.@.\n...\n", p()).unwrap();
        assert_eq!(f, MapFormat::MovingAi);
        assert_eq!((m.width(), m.height()), (3, 2));
        assert_eq!(m.graph().num_vertices(), 5);
        let v = m.vertex_at(0, 1).unwrap();
        assert_eq!(m.cell(v), (0, 1));
        assert_eq!(m.graph().degree(v), 2);
        assert!(m.vertex_at(1, 0).is_none());
    }

    #[test]
    fn movingai_headers_in_any_order_without_type_and_every_terrain_character() {
        let with =
            GridMap::parse("type octile\nheight 2\nwidth 4\nmap\n.GS@\nOTW.\n", p()).unwrap();
        for text in [
            "height 2\nwidth 4\nmap\n.GS@\nOTW.\n",
            "width 4\nheight 2\nmap\n.GS@\nOTW.\n",
            "width 4\ntype octile\nheight 2\nmap\n.GS@\nOTW.\n",
        ] {
            let (m, f) = GridMap::parse(text, p()).unwrap();
            assert_eq!(f, MapFormat::MovingAi, "{text}");
            assert_eq!((m.width(), m.height()), (4, 2));
            for (x, y) in [(0, 0), (1, 0), (2, 0), (3, 1)] {
                assert!(m.is_free(x, y), "({x},{y}) in {text}");
            }
            for (x, y) in [(3, 0), (0, 1), (1, 1), (2, 1)] {
                assert!(!m.is_free(x, y), "({x},{y}) in {text}");
            }
            assert_eq!(m.graph().num_vertices(), with.0.graph().num_vertices());
        }
    }

    #[test]
    fn movingai_text_reads_back_to_the_same_map() {
        let (a, _) = GridMap::parse("####\n#  #\n# ##\n", p()).unwrap();
        let text = a.movingai_text();
        assert_eq!(
            text,
            "type octile\nheight 3\nwidth 4\nmap\n@@@@\n@..@\n@.@@\n"
        );
        let (b, f) = GridMap::parse(&text, p()).unwrap();
        assert_eq!(f, MapFormat::MovingAi);
        assert_eq!(
            (b.width(), b.height(), b.free.clone()),
            (a.width(), a.height(), a.free)
        );
    }

    #[test]
    fn truncated_movingai_names_line() {
        let err =
            GridMap::parse("type octile\nheight 3\nwidth 3\nmap\n...\n...\n", p()).unwrap_err();
        let msg = err.to_string();
        assert!(msg.starts_with("test.map:7:"), "{msg}");
        assert!(msg.contains("truncated"), "{msg}");
    }

    #[test]
    fn ascii_map_with_crlf_and_no_final_newline() {
        let (m, f) = GridMap::parse("####\r\n#  #\r\n####", p()).unwrap();
        assert_eq!(f, MapFormat::Ascii);
        assert_eq!((m.width(), m.height()), (4, 3));
        assert_eq!(m.graph().num_vertices(), 2);
        assert!(m.is_free(1, 1) && !m.is_free(0, 0));
    }

    #[test]
    fn ascii_bad_character_is_reported() {
        let err = GridMap::parse("###\n#x#\n###\n", p())
            .unwrap_err()
            .to_string();
        assert!(err.starts_with("test.map:2:"), "{err}");
    }

    #[test]
    fn map_without_free_cells_is_rejected() {
        assert!(GridMap::parse("###\n###\n", p()).is_err());
    }
}
