//! The competition's road features (`test_analysis.py`): MAX_CURV and DIR_COV.

use super::circle;
use super::Point;
use serde::{Deserialize, Serialize};

/// Number of edges of the direction-coverage buckets (`linspace(0, 360, 26)`).
const DIRECTION_BUCKET_EDGES: usize = 26;

/// The road features the competition reports for every test.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RoadFeatures {
    /// Largest curvature over the sharpness windows, 1/m.
    #[serde(rename = "MAX_CURV")]
    pub max_curvature: f64,
    /// Share of direction buckets the road's segments cover.
    #[serde(rename = "DIR_COV")]
    pub direction_coverage: f64,
}

impl RoadFeatures {
    /// Features of an interpolated centre line.
    pub fn of(interpolated: &[Point]) -> Self {
        Self {
            max_curvature: max_curvature(interpolated),
            direction_coverage: direction_coverage(interpolated),
        }
    }
}

/// `1 / min radius` over the sharpness windows (0 for a straight road), 1/m.
pub fn max_curvature(interpolated: &[Point]) -> f64 {
    1.0 / circle::min_radius(interpolated)
}

/// Direction coverage: the angle of each segment to north, in degrees, put in buckets of
/// 360/25 degrees; the number of distinct buckets hit over 26.
pub fn direction_coverage(interpolated: &[Point]) -> f64 {
    let bucket_width = 360.0 / (DIRECTION_BUCKET_EDGES - 1) as f64;
    let mut hit = [false; DIRECTION_BUCKET_EDGES + 1];
    for w in interpolated.windows(2) {
        let (dx, dy) = (w[1][0] - w[0][0], w[1][1] - w[0][1]);
        let cosine = dy / dx.hypot(dy);
        let angle_deg = cosine.acos().to_degrees();
        // numpy.digitize: index i with edge[i-1] <= angle < edge[i]; NaN falls past the last edge.
        let bucket = if angle_deg.is_nan() {
            DIRECTION_BUCKET_EDGES
        } else {
            (0..DIRECTION_BUCKET_EDGES)
                .take_while(|&k| k as f64 * bucket_width <= angle_deg)
                .count()
        };
        hit[bucket] = true;
    }
    hit.iter().filter(|&&h| h).count() as f64 / DIRECTION_BUCKET_EDGES as f64
}
