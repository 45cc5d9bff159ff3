//! A road's shape as the search compares roads (niches, shape novelty, regression suites): its
//! centre line resampled to [`PROFILE_POINTS`] points evenly spaced by arc length, and the heading
//! of each of the segments between them relative to the first, unwrapped, in radians. Unwrapped,
//! it changes continuously with the road; the paper's diversity measure describes roads by
//! wrapped angles instead ([`super::diversity_profile`]).

use super::Point;

/// Points of the resampled centre line (so the profile has one value fewer).
pub const PROFILE_POINTS: usize = 75;

/// The unwrapped headings of `line` (at least two points): [`PROFILE_POINTS`] − 1 values,
/// radians.
pub fn heading_profile(line: &[Point]) -> Vec<f64> {
    let resampled = resample_by_arc_length(line, PROFILE_POINTS);
    let mut profile = Vec::with_capacity(PROFILE_POINTS - 1);
    let mut previous: Option<f64> = None;
    let mut unwrapped = 0.0;
    for w in resampled.windows(2) {
        let heading = (w[1][1] - w[0][1]).atan2(w[1][0] - w[0][0]);
        if let Some(previous) = previous {
            // Unwrap: between neighbouring samples a road never turns by half a revolution.
            let turn = heading - previous;
            unwrapped += turn - std::f64::consts::TAU * (turn / std::f64::consts::TAU).round();
        }
        previous = Some(heading);
        profile.push(unwrapped);
    }
    profile
}

/// How far `line` (at least two points) turns from its first heading at most, either way: the
/// largest magnitude of its [`heading_profile`], radians.
pub fn largest_turn_rad(line: &[Point]) -> f64 {
    heading_profile(line)
        .into_iter()
        .fold(0.0, |largest, heading| largest.max(heading.abs()))
}

/// `count` points along `line`, evenly spaced by arc length, first and last included.
pub fn resample_by_arc_length(line: &[Point], count: usize) -> Vec<Point> {
    let mut cumulative = Vec::with_capacity(line.len());
    let mut total = 0.0;
    cumulative.push(0.0);
    for w in line.windows(2) {
        total += (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]);
        cumulative.push(total);
    }
    let mut segment = 0;
    (0..count)
        .map(|i| {
            let target = total * i as f64 / (count - 1) as f64;
            while segment + 2 < line.len() && cumulative[segment + 1] < target {
                segment += 1;
            }
            let span = cumulative[segment + 1] - cumulative[segment];
            let t = if span > 0.0 {
                ((target - cumulative[segment]) / span).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let (a, b) = (line[segment], line[segment + 1]);
            [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn straight_line_has_a_flat_profile() {
        let profile = heading_profile(&[[0.0, 0.0], [3.0, 4.0], [30.0, 40.0]]);
        assert_eq!(profile.len(), PROFILE_POINTS - 1);
        assert!(profile.iter().all(|h| h.abs() < 1e-12));
    }

    #[test]
    fn the_largest_turn_is_the_farthest_either_way_from_the_start() {
        assert!(largest_turn_rad(&[[0.0, 0.0], [3.0, 4.0], [30.0, 40.0]]) < 1e-12);
        // A quarter turn right (clockwise), then 225° left: 90° right of the start at most that
        // way, 135° left of it at the end.
        let right = (0..=90).map(|i| {
            let a = f64::from(i).to_radians();
            [50.0 - 50.0 * a.cos(), 50.0 * a.sin()]
        });
        let left = (1..=225).map(|i| {
            let a = f64::from(i).to_radians();
            [50.0 + 50.0 * a.sin(), 50.0 + 50.0 - 50.0 * a.cos()]
        });
        let line: Vec<Point> = right.chain(left).collect();
        let largest = largest_turn_rad(&line);
        assert!(
            (largest - 0.75 * std::f64::consts::PI).abs() < 0.05,
            "{largest}"
        );
    }

    #[test]
    fn a_full_circle_unwraps_to_a_whole_turn() {
        let circle: Vec<Point> = (0..=720)
            .map(|i| {
                let a = i as f64 / 720.0 * std::f64::consts::TAU;
                [50.0 * a.cos(), 50.0 * a.sin()]
            })
            .collect();
        let profile = heading_profile(&circle);
        let last = *profile.last().unwrap();
        // 74 segments over one revolution: the last is 73/74 of a turn after the first.
        assert!(
            (last - std::f64::consts::TAU * 73.0 / 74.0).abs() < 0.01,
            "{last}"
        );
        assert!(profile.windows(2).all(|w| w[1] > w[0]));
    }
}
