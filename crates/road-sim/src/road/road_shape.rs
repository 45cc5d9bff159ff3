//! What a search compares roads by: the heading profile, or the WOGAN authors' diversity
//! description. Both describe a road by its directions at points evenly spaced along it; they
//! differ in whether a turn past half a circle goes on growing or wraps.

use super::diversity_profile::diversity_profile;
use super::heading_profile::heading_profile;
use super::Point;
use serde::{Deserialize, Serialize};

/// How a search's niches and its shape novelty rule compare roads (`wogan run --road-shape`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RoadShape {
    /// The heading profile: headings unwrapped, at points evenly spaced by arc length; it
    /// changes continuously with the road.
    #[default]
    Headings,
    /// The WOGAN authors' diversity description: directions from north, not unwrapped, so that
    /// roads far apart by the paper's diversity are far apart here too.
    Directions,
}

impl RoadShape {
    /// Whether this is the default, [`RoadShape::Headings`] (files written before there was a
    /// choice say nothing).
    pub fn is_headings(&self) -> bool {
        *self == Self::Headings
    }

    /// The description of the road through `interpolated` (radians).
    pub fn profile(self, interpolated: &[Point]) -> Vec<f64> {
        match self {
            Self::Headings => heading_profile(interpolated),
            Self::Directions => diversity_profile(interpolated),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Points about 1 m apart along an arc of `radius_m` turning `turn_rad`, from the origin.
    fn arc(radius_m: f64, turn_rad: f64) -> Vec<Point> {
        let points = (radius_m * turn_rad).ceil() as usize + 1;
        (0..points)
            .map(|i| {
                let angle = turn_rad * i as f64 / (points - 1) as f64;
                [radius_m * (1.0 - angle.cos()), radius_m * angle.sin()]
            })
            .collect()
    }

    #[test]
    fn directions_wrap_where_headings_go_on_past_half_a_turn() {
        let road = arc(40.0, 1.5 * PI);
        let headings = RoadShape::Headings.profile(&road);
        let directions = RoadShape::Directions.profile(&road);
        assert_eq!(headings, heading_profile(&road));
        assert_eq!(directions, diversity_profile(&road));
        let largest = |profile: &[f64]| profile.iter().fold(0.0_f64, |m, h| m.max(h.abs()));
        assert!(largest(&headings) > 4.0, "headings unwrapped: {headings:?}");
        assert!(
            largest(&directions) <= PI,
            "directions wrapped: {directions:?}"
        );
    }

    #[test]
    fn the_default_shape_is_the_heading_profile_and_shapes_are_written_by_name() {
        assert_eq!(RoadShape::default(), RoadShape::Headings);
        assert!(RoadShape::default().is_headings());
        let written = serde_json::to_string(&RoadShape::Directions).unwrap();
        assert_eq!(written, "\"directions\"");
    }
}
