//! What the validator answers: valid, or the first rule a road breaks.

use crate::road::Road;
use serde::{Deserialize, Serialize};

/// Why a road is invalid: a stable code for machines plus the competition's message.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Reason {
    /// Fewer than two road points.
    NotEnoughPoints,
    /// More than [`MAX_ROAD_POINTS`](super::MAX_ROAD_POINTS) road points.
    TooManyPoints,
    /// Non-finite coordinates, repeated consecutive points or a degenerate interpolation.
    Malformed,
    /// Part of the road polygon lies on or outside the map's border.
    OutsideMap,
    /// The road polygon overlaps itself.
    SelfIntersecting,
    /// The centre line is not longer than [`MIN_LENGTH_M`](super::rules::MIN_LENGTH_M).
    TooShort,
    /// A turn is tighter than [`MIN_RADIUS_FT`](super::rules::MIN_RADIUS_FT).
    TooSharp,
    /// The polyline through the points is longer than [`MAX_ROAD_LENGTH_M`](super::MAX_ROAD_LENGTH_M) (our bound, not the
    /// competition's: on its 200 m map no valid road comes near it).
    TooLong,
}

impl Reason {
    /// The stable reason code (`outside_map`, ...).
    pub fn code(self) -> &'static str {
        match self {
            Reason::NotEnoughPoints => "not_enough_points",
            Reason::TooManyPoints => "too_many_points",
            Reason::Malformed => "malformed",
            Reason::OutsideMap => "outside_map",
            Reason::SelfIntersecting => "self_intersecting",
            Reason::TooShort => "too_short",
            Reason::TooSharp => "too_sharp",
            Reason::TooLong => "too_long",
        }
    }

    /// The competition's message for this reason.
    pub fn message(self) -> &'static str {
        match self {
            Reason::NotEnoughPoints => "Not enough road points.",
            Reason::TooManyPoints => "The road definition contains too many points",
            Reason::Malformed => "The road points are malformed",
            Reason::OutsideMap => "Not entirely inside the map boundaries",
            Reason::SelfIntersecting => "The road is self-intersecting",
            Reason::TooShort => "The road is not long enough.",
            Reason::TooSharp => "The road is too sharp",
            Reason::TooLong => "The road is longer than 20 km",
        }
    }
}

impl std::fmt::Display for Reason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.code())
    }
}

/// The validator's answer for one road.
#[derive(Debug, Clone)]
pub struct Verdict {
    /// `None` when the road is valid.
    pub reason: Option<Reason>,
    /// The interpolated road, when the points could be interpolated.
    pub road: Option<Road>,
}

impl Verdict {
    /// Whether the road is valid.
    pub fn is_valid(&self) -> bool {
        self.reason.is_none()
    }

    /// The competition's message (empty for a valid road).
    pub fn message(&self) -> &'static str {
        self.reason.map_or("", Reason::message)
    }
}
