//! A road as the competition sees it: the interpolated centre line, its edges, the road polygon's
//! quads, the right lane and the lane centre lines.

use super::spline::{self, SplineError};
use super::Point;

/// Width of the road (two lanes), metres.
pub const ROAD_WIDTH_M: f64 = 8.0;
/// Width of one lane, metres.
pub const LANE_WIDTH_M: f64 = ROAD_WIDTH_M / 2.0;

/// A road built from its defining points.
#[derive(Debug, Clone)]
pub struct Road {
    /// The points the road was defined by.
    pub road_points: Vec<Point>,
    /// The centre line, interpolated as the competition does (about 1 m apart, 3 decimals).
    pub interpolated: Vec<Point>,
    /// Unit left normal at each interpolated point (of the segment that starts there; the last
    /// point uses the previous segment).
    pub left_normals: Vec<Point>,
}

/// Why road points do not make a road whose geometry can be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RoadError {
    /// The spline through the points cannot be built.
    #[error(transparent)]
    Spline(#[from] SplineError),
    /// Two consecutive interpolated points coincide after rounding, so the road has no direction
    /// there.
    #[error("interpolated points {0} and {1} coincide")]
    DegenerateSegment(usize, usize),
}

impl Road {
    /// Interpolates `road_points` and computes the normals of the centre line.
    pub fn new(road_points: &[Point]) -> Result<Self, RoadError> {
        let interpolated = spline::interpolate(road_points)?;
        let mut left_normals = Vec::with_capacity(interpolated.len());
        for (i, w) in interpolated.windows(2).enumerate() {
            let (dx, dy) = (w[1][0] - w[0][0], w[1][1] - w[0][1]);
            let length = dx.hypot(dy);
            if length == 0.0 || !length.is_finite() {
                return Err(RoadError::DegenerateSegment(i, i + 1));
            }
            left_normals.push([-dy / length, dx / length]);
        }
        let last = *left_normals
            .last()
            .expect("interpolation gives at least 21 points");
        left_normals.push(last);
        Ok(Self {
            road_points: road_points.to_vec(),
            interpolated,
            left_normals,
        })
    }

    /// The point at `offset_m` to the left of interpolated point `i` (negative: to the right).
    pub fn offset_point(&self, i: usize, offset_m: f64) -> Point {
        let (p, n) = (self.interpolated[i], self.left_normals[i]);
        [p[0] + offset_m * n[0], p[1] + offset_m * n[1]]
    }

    /// A line parallel to the centre line, `offset_m` to its left (negative: right).
    pub fn offset_line(&self, offset_m: f64) -> Vec<Point> {
        (0..self.interpolated.len())
            .map(|i| self.offset_point(i, offset_m))
            .collect()
    }

    /// The road's left edge.
    pub fn left_edge(&self) -> Vec<Point> {
        self.offset_line(ROAD_WIDTH_M / 2.0)
    }

    /// The road's right edge.
    pub fn right_edge(&self) -> Vec<Point> {
        self.offset_line(-ROAD_WIDTH_M / 2.0)
    }

    /// Centre line of the right lane, where the car drives.
    pub fn right_lane_centre(&self) -> Vec<Point> {
        self.offset_line(-LANE_WIDTH_M / 2.0)
    }

    /// Centre line of the left lane.
    pub fn left_lane_centre(&self) -> Vec<Point> {
        self.offset_line(LANE_WIDTH_M / 2.0)
    }

    /// The road polygon's quads: for each centre-line segment `i`, the corners
    /// `[left_i, left_i+1, right_i+1, right_i]`.
    pub fn quads(&self) -> Vec<[Point; 4]> {
        let left = self.left_edge();
        let right = self.right_edge();
        (0..self.interpolated.len() - 1)
            .map(|i| [left[i], left[i + 1], right[i + 1], right[i]])
            .collect()
    }

    /// The right lane's polygon over interpolated points `first..=last`: forward along the centre
    /// line, back along the right edge. The whole lane is `right_lane_polygon(0, len - 1)`.
    pub fn right_lane_polygon(&self, first: usize, last: usize) -> Vec<Point> {
        let mut polygon: Vec<Point> = self.interpolated[first..=last].to_vec();
        polygon.extend(
            (first..=last)
                .rev()
                .map(|i| self.offset_point(i, -ROAD_WIDTH_M / 2.0)),
        );
        polygon
    }

    /// Length of the interpolated centre line, metres.
    pub fn length_m(&self) -> f64 {
        spline::polyline_length(&self.interpolated)
    }
}
