//! The road as the camera's world: the flat ground's surfaces (grass, asphalt, a solid yellow
//! centre line, white edge lines) and their colours, and a road prepared for finding which one a
//! ground point shows.
//!
//! Speed: the distance to the road's centre line is found through a uniform grid of the centre
//! line's segments built once per road ([`RoadScene::new`]); with it comes a margin within which
//! a point's surface cannot change, which lets the camera fill runs of pixels without a search.

use crate::road::{Point, Road, ROAD_WIDTH_M};

/// Width of the painted lines (yellow centre line, white edge lines), metres.
pub const LINE_WIDTH_M: f64 = 0.15;
/// Distance of the white edge lines' outer border inside the road's edge, metres.
pub const EDGE_LINE_INSET_M: f64 = 0.1;

/// What a ground (or sky) point shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum Surface {
    /// Above the horizon.
    Sky = 0,
    /// Off the road.
    Grass = 1,
    /// Road surface.
    Asphalt = 2,
    /// The centre line.
    Yellow = 3,
    /// An edge line.
    White = 4,
}

/// Colours of the surfaces, RGB.
pub const RGB: [[u8; 3]; 5] = [
    [135, 180, 230],
    [60, 120, 50],
    [75, 75, 80],
    [230, 200, 40],
    [240, 240, 240],
];

/// Gray levels of the surfaces (the luma of [`RGB`], ITU-R BT.601).
pub const GRAY: [u8; 5] = gray_levels();

const fn gray_levels() -> [u8; 5] {
    let mut g = [0u8; 5];
    let mut i = 0;
    while i < 5 {
        let [r, gr, b] = RGB[i];
        g[i] = ((299 * r as u32 + 587 * gr as u32 + 114 * b as u32 + 500) / 1000) as u8;
        i += 1;
    }
    g
}

/// Half-width of the band around the centre line where anything but grass can be, metres.
const REACH_M: f64 = ROAD_WIDTH_M / 2.0;
/// Grid cell size, metres.
const CELL_M: f64 = 1.0;

/// A centre-line segment: start, unit direction, length; the first and last segments know that
/// the road ends at their outer ends.
#[derive(Debug, Clone, Copy)]
struct Segment {
    a: [f64; 2],
    dir: [f64; 2],
    length: f64,
    open_start: bool,
    open_end: bool,
}

/// A road prepared for rendering: its centre-line segments in a uniform grid (each cell lists
/// the segments that come within half the road's width of it).
#[derive(Debug, Clone)]
pub struct RoadScene {
    segments: Vec<Segment>,
    /// The centre line's first and last points.
    ends: [Point; 2],
    origin: [f64; 2],
    cols: usize,
    rows: usize,
    /// CSR: cell `k`'s segments are `items[starts[k]..starts[k + 1]]`.
    starts: Vec<u32>,
    items: Vec<u32>,
}

impl RoadScene {
    /// Prepares `road` (its interpolated centre line).
    pub fn new(road: &Road) -> Self {
        let c = &road.interpolated;
        let n = c.len().saturating_sub(1);
        let mut segments = Vec::with_capacity(n);
        for i in 0..n {
            let (a, b) = (c[i], c[i + 1]);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let length = dx.hypot(dy);
            let dir = if length > 0.0 {
                [dx / length, dy / length]
            } else {
                [1.0, 0.0]
            };
            segments.push(Segment {
                a,
                dir,
                length,
                open_start: i == 0,
                open_end: i + 1 == n,
            });
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in c {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if segments.is_empty() {
            return Self {
                segments,
                ends: [[f64::NAN; 2]; 2],
                origin: [0.0; 2],
                cols: 0,
                rows: 0,
                starts: vec![0],
                items: Vec::new(),
            };
        }
        let origin = [lo[0] - REACH_M - CELL_M, lo[1] - REACH_M - CELL_M];
        let cols = ((hi[0] + REACH_M + CELL_M - origin[0]) / CELL_M).ceil() as usize + 1;
        let rows = ((hi[1] + REACH_M + CELL_M - origin[1]) / CELL_M).ceil() as usize + 1;
        let cell_range = |s: &Segment| {
            let b = [s.a[0] + s.dir[0] * s.length, s.a[1] + s.dir[1] * s.length];
            let x0 = ((s.a[0].min(b[0]) - REACH_M - origin[0]) / CELL_M).floor() as usize;
            let x1 = ((s.a[0].max(b[0]) + REACH_M - origin[0]) / CELL_M).floor() as usize;
            let y0 = ((s.a[1].min(b[1]) - REACH_M - origin[1]) / CELL_M).floor() as usize;
            let y1 = ((s.a[1].max(b[1]) + REACH_M - origin[1]) / CELL_M).floor() as usize;
            (x0, x1.min(cols - 1), y0, y1.min(rows - 1))
        };
        // Whether segment `s` comes within `REACH_M` of some point of cell `(x, y)`
        // (conservatively: of a disc around the cell's centre that covers the cell).
        let touches = |s: &Segment, x: usize, y: usize| {
            let cx = origin[0] + (x as f64 + 0.5) * CELL_M - s.a[0];
            let cy = origin[1] + (y as f64 + 0.5) * CELL_M - s.a[1];
            let t = (cx * s.dir[0] + cy * s.dir[1]).clamp(0.0, s.length);
            let r = REACH_M + CELL_M * std::f64::consts::FRAC_1_SQRT_2 + 1e-9;
            (cx - t * s.dir[0]).powi(2) + (cy - t * s.dir[1]).powi(2) <= r * r
        };
        let mut counts = vec![0u32; cols * rows + 1];
        for s in &segments {
            let (x0, x1, y0, y1) = cell_range(s);
            for y in y0..=y1 {
                for x in (x0..=x1).filter(|&x| touches(s, x, y)) {
                    counts[y * cols + x + 1] += 1;
                }
            }
        }
        for k in 1..counts.len() {
            counts[k] += counts[k - 1];
        }
        let starts = counts;
        let mut fill = starts.clone();
        let mut items = vec![0u32; *starts.last().unwrap_or(&0) as usize];
        for (i, s) in segments.iter().enumerate() {
            let (x0, x1, y0, y1) = cell_range(s);
            for y in y0..=y1 {
                for x in (x0..=x1).filter(|&x| touches(s, x, y)) {
                    let k = y * cols + x;
                    items[fill[k] as usize] = i as u32;
                    fill[k] += 1;
                }
            }
        }
        Self {
            segments,
            ends: [c[0], c[c.len() - 1]],
            origin,
            cols,
            rows,
            starts,
            items,
        }
    }

    /// Distance from `p` to the centre line if it is within half the road's width (the road
    /// ends squarely at its first and last points); `None` farther away.
    pub fn centre_distance(&self, p: Point) -> Option<f64> {
        let fx = (p[0] - self.origin[0]) / CELL_M;
        let fy = (p[1] - self.origin[1]) / CELL_M;
        if !(fx >= 0.0 && fy >= 0.0) {
            return None;
        }
        let (x, y) = (fx as usize, fy as usize);
        if x >= self.cols || y >= self.rows {
            return None;
        }
        let k = y * self.cols + x;
        let mut best = REACH_M * REACH_M;
        let mut found = false;
        for &i in &self.items[self.starts[k] as usize..self.starts[k + 1] as usize] {
            let s = &self.segments[i as usize];
            let (dx, dy) = (p[0] - s.a[0], p[1] - s.a[1]);
            let t = dx * s.dir[0] + dy * s.dir[1];
            if (s.open_start && t < 0.0) || (s.open_end && t > s.length) {
                continue;
            }
            let t = t.clamp(0.0, s.length);
            let (ex, ey) = (dx - t * s.dir[0], dy - t * s.dir[1]);
            let d2 = ex * ex + ey * ey;
            if d2 < best {
                best = d2;
                found = true;
            }
        }
        found.then(|| best.sqrt())
    }

    /// What the ground shows at `p`.
    pub fn surface(&self, p: Point) -> Surface {
        self.surface_and_margin(p).0
    }

    /// What the ground shows at `p`, and a distance (metres, maybe 0) that `p` can move without
    /// that changing: the distance to the centre line is 1-Lipschitz, and the road's square ends
    /// matter only within half a road's width of its end points.
    pub(super) fn surface_and_margin(&self, p: Point) -> (Surface, f64) {
        let Some(d) = self.centre_distance(p) else {
            return (Surface::Grass, 0.0);
        };
        let edge_outer = REACH_M - EDGE_LINE_INSET_M;
        let edge_inner = edge_outer - LINE_WIDTH_M;
        let surface = if d <= LINE_WIDTH_M / 2.0 {
            Surface::Yellow
        } else if d <= edge_outer && d > edge_inner {
            Surface::White
        } else if d < REACH_M {
            Surface::Asphalt
        } else {
            Surface::Grass
        };
        let mut margin = f64::INFINITY;
        for b in [LINE_WIDTH_M / 2.0, edge_inner, edge_outer, REACH_M] {
            margin = margin.min((d - b).abs());
        }
        for e in self.ends {
            margin = margin.min((p[0] - e[0]).hypot(p[1] - e[1]) - REACH_M);
        }
        // Keep well clear of the boundaries (rounding).
        (surface, (margin - 1e-6).max(0.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gray_levels_are_distinct() {
        for (i, a) in GRAY.iter().enumerate() {
            assert!(GRAY[..i].iter().all(|b| b != a), "{GRAY:?}");
        }
    }

    #[test]
    fn grid_matches_brute_force() {
        let pts: Vec<Point> = vec![[50.0, 10.0], [60.0, 60.0], [100.0, 90.0], [150.0, 60.0]];
        let road = Road::new(&pts).unwrap();
        let scene = RoadScene::new(&road);
        let c = &road.interpolated;
        let n = c.len() - 1;
        let mut k = 0u64;
        for ix in 0..120 {
            for iy in 0..120 {
                k = k
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let p = [
                    30.0 + ix as f64 * 1.1 + (k >> 40) as f64 / 1e8,
                    0.0 + iy as f64 * 1.0,
                ];
                let mut best = f64::INFINITY;
                for i in 0..n {
                    let (a, b) = (c[i], c[i + 1]);
                    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
                    let l2 = dx * dx + dy * dy;
                    let t = ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2;
                    if (i == 0 && t < 0.0) || (i + 1 == n && t > 1.0) {
                        continue;
                    }
                    let t = t.clamp(0.0, 1.0);
                    best = best.min((p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dy));
                }
                let got = scene.centre_distance(p);
                if best < REACH_M - 1e-9 {
                    let d = got.unwrap_or_else(|| panic!("{p:?}: none, expected {best}"));
                    assert!((d - best).abs() < 1e-9, "{p:?}: {d} vs {best}");
                } else if best > REACH_M + 1e-9 {
                    assert!(got.is_none(), "{p:?}: {got:?} vs {best}");
                }
            }
        }
    }
}
