//! The sparse curvature representation of roads used by Frenetic and WOGAN.
//!
//! A road is a short list of curvature values (1/m). It starts at the bottom centre of the map
//! heading north, goes one step straight ahead, and before each further step turns by the
//! trapezoid-rule integral of the curvature over that step.

use super::Point;
use serde::{Deserialize, Serialize};

/// The paper's bound on each curvature value, 1/m.
pub const MAX_CURVATURE_PER_M: f64 = 0.07;
/// The paper's distance between consecutive road points, metres.
pub const DEFAULT_STEP_M: f64 = 15.0;
/// Distance of the first road point from the map's bottom edge, metres.
pub const START_Y_M: f64 = 10.0;

/// How curvature values become road points.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct CurvatureRoad {
    /// Side of the square map, metres.
    pub map_size_m: f64,
    /// Distance between consecutive road points, metres.
    pub step_m: f64,
}

impl Default for CurvatureRoad {
    fn default() -> Self {
        Self {
            map_size_m: 200.0,
            step_m: DEFAULT_STEP_M,
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
    fn constant_curvature_turns_left_by_step_times_curvature() {
        let points = CurvatureRoad::default().points(&[0.05; 3]);
        let heading = |a: Point, b: Point| (b[1] - a[1]).atan2(b[0] - a[0]);
        let turn = heading(points[2], points[3]) - heading(points[1], points[2]);
        assert!((turn - 15.0 * 0.05).abs() < 1e-12);
    }
}
