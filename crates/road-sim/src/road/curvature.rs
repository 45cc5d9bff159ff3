//! The sparse curvature representation of roads used by Frenetic and WOGAN.
//!
//! A road is a short list of curvature values (1/m). It starts at the bottom centre of the map
//! heading north, goes one step straight ahead, and before each further step turns by the
//! trapezoid-rule integral of the curvature over that step. With [`RoadPlacement::Fitted`] a road
//! that leaves the map from there is turned and moved until it fits, as the Frenetic generators
//! place theirs, so that roads which swing far are not lost to the map's edges.

use super::Point;
use serde::{Deserialize, Serialize};

/// The paper's bound on each curvature value, 1/m.
pub const MAX_CURVATURE_PER_M: f64 = 0.07;
/// The paper's distance between consecutive road points, metres.
pub const DEFAULT_STEP_M: f64 = 15.0;
/// Distance of the first road point from the map's bottom edge, metres.
pub const START_Y_M: f64 = 10.0;

/// Distance a fitted road's points keep from the map's edges, metres (the start's distance from
/// the bottom edge: room for the road's half width and the spline between points).
pub const FIT_MARGIN_M: f64 = START_Y_M;
/// Rotations tried when fitting a road, whole degrees from 0 (a quarter turn: with the move that
/// follows, the other quarters add no fit a square map does not already give).
const FIT_ROTATIONS_DEG: u32 = 90;

/// Where a road lies on the map.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RoadPlacement {
    /// From the bottom centre heading north (stgem's placement of WOGAN's roads, the paper's).
    #[default]
    BottomCentre,
    /// As `BottomCentre` when the road's points keep [`FIT_MARGIN_M`] from every edge; otherwise
    /// turned by the fewest whole degrees (0–89) after which, moved to [`FIT_MARGIN_M`] from the
    /// left and bottom edges, they do; left where it was when no turn fits.
    Fitted,
}

/// How curvature values become road points.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct CurvatureRoad {
    /// Side of the square map, metres.
    pub map_size_m: f64,
    /// Distance between consecutive road points, metres.
    pub step_m: f64,
    /// Where the road lies on the map.
    pub placement: RoadPlacement,
}

impl Default for CurvatureRoad {
    fn default() -> Self {
        Self {
            map_size_m: 200.0,
            step_m: DEFAULT_STEP_M,
            placement: RoadPlacement::BottomCentre,
        }
    }
}

impl CurvatureRoad {
    /// Road points for `curvature` (1/m): `curvature.len() + 1` points.
    pub fn points(&self, curvature: &[f64]) -> Vec<Point> {
        let mut position = [self.map_size_m / 2.0, START_Y_M];
        let mut heading = std::f64::consts::FRAC_PI_2;
        let mut points = Vec::with_capacity(curvature.len() + 1);
        points.push(position);
        for i in 0..curvature.len() {
            if i > 0 {
                heading += self.step_m * (curvature[i - 1] + curvature[i]) / 2.0;
            }
            position = [
                position[0] + self.step_m * heading.cos(),
                position[1] + self.step_m * heading.sin(),
            ];
            points.push(position);
        }
        match self.placement {
            RoadPlacement::BottomCentre => points,
            RoadPlacement::Fitted => self.fitted(points),
        }
    }

    /// `points` turned and moved to keep [`FIT_MARGIN_M`] from the map's edges, or as they are
    /// when they already do or no turn makes them.
    fn fitted(&self, points: Vec<Point>) -> Vec<Point> {
        let (low, high) = (FIT_MARGIN_M, self.map_size_m - FIT_MARGIN_M);
        let fits = |p: &[Point]| p.iter().flatten().all(|&v| (low..=high).contains(&v));
        if fits(&points) {
            return points;
        }
        for degrees in 0..FIT_ROTATIONS_DEG {
            let (sin, cos) = f64::from(degrees).to_radians().sin_cos();
            let mut turned: Vec<Point> = points
                .iter()
                .map(|p| [p[0] * cos - p[1] * sin, p[0] * sin + p[1] * cos])
                .collect();
            let min = |axis: usize| turned.iter().map(|p| p[axis]).fold(f64::INFINITY, f64::min);
            let shift = [low - min(0), low - min(1)];
            for p in &mut turned {
                p[0] += shift[0];
                p[1] += shift[1];
            }
            if fits(&turned) {
                return turned;
            }
        }
        points
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_curvature_is_a_straight_road_north() {
        let points = CurvatureRoad::default().points(&[0.0; 5]);
        assert_eq!(points.len(), 6);
        for (i, p) in points.iter().enumerate() {
            assert!((p[0] - 100.0).abs() < 1e-9);
            assert!((p[1] - (10.0 + 15.0 * i as f64)).abs() < 1e-9);
        }
    }

    #[test]
    fn a_fitted_road_keeps_its_shape_and_the_map() {
        // A steady left turn of 180 m swings far west of the start and off the map there.
        let curvature = [0.02; 12];
        let start = CurvatureRoad::default().points(&curvature);
        assert!(start.iter().any(|p| p[0] < FIT_MARGIN_M));
        let fitted = CurvatureRoad {
            placement: RoadPlacement::Fitted,
            ..CurvatureRoad::default()
        }
        .points(&curvature);
        assert!(fitted
            .iter()
            .flatten()
            .all(|&v| (FIT_MARGIN_M..=200.0 - FIT_MARGIN_M).contains(&v)));
        // Turned and moved, not bent: every distance between points is kept.
        let distance = |a: Point, b: Point| (a[0] - b[0]).hypot(a[1] - b[1]);
        for i in 0..start.len() {
            for j in i + 1..start.len() {
                let (d0, d1) = (distance(start[i], start[j]), distance(fitted[i], fitted[j]));
                assert!((d0 - d1).abs() < 1e-9, "{d0} against {d1}");
            }
        }
        // A road that fits where it starts stays there.
        let straight = [0.0; 5];
        assert_eq!(
            CurvatureRoad {
                placement: RoadPlacement::Fitted,
                ..CurvatureRoad::default()
            }
            .points(&straight),
            CurvatureRoad::default().points(&straight)
        );
    }

    #[test]
    fn constant_curvature_turns_left_by_step_times_curvature() {
        let points = CurvatureRoad::default().points(&[0.05; 3]);
        let heading = |a: Point, b: Point| (b[1] - a[1]).atan2(b[0] - a[0]);
        let turn = heading(points[2], points[3]) - heading(points[1], points[2]);
        assert!((turn - 15.0 * 0.05).abs() < 1e-12);
    }
}
