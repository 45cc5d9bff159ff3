//! Distinct failures: how many of a set of failing roads differ where the car left its lane.
//!
//! The WOGAN paper's diversity (the median pairwise distance of whole roads' directions,
//! [`crate::road::diversity_profile`]) is no count: finding a second, larger cluster of failures
//! can lower it, and describing every road by 75 of its points compares a long road's shape with
//! a short one's at different scales. This module counts instead, and looks only where a failure
//! happened:
//!
//! - **Exit profile** ([`ExitProfile::of`]): the road's centre line from [`REACH_M`] before to
//!   [`REACH_M`] after the point nearest the lane exit (arc length, the competition's ±30 m OOB
//!   segments), sampled every [`STEP_M`]: the heading of each 1 m chord relative to the chord at
//!   the exit, unwrapped, radians ([`PROFILE_LEN`] values). Relative headings make it blind to
//!   where the bend lies on the map and which way it points (translation and rotation), but not to
//!   which way it turns: a left bend and its mirror are different failures for a driver in the
//!   right lane, so mirrored profiles are not merged. Where the window runs past the road's start
//!   or end the road is taken to go on straight (a car starts on the road aligned with it, and
//!   past the end there is nothing to turn), so every profile covers the same 60 m: no road is
//!   compared over less road than another, whatever its length.
//! - **Distance** ([`ExitProfile::distance`]): the root mean square of the two profiles'
//!   differences, radians; a metric (a scaled Euclidean distance of fixed-length vectors).
//! - **Count** ([`distinct`]): failures taken in the order given (a run's test order), each kept
//!   when it lies at least [`DELTA_RAD`] from every failure kept before it. The kept set is
//!   δ-separated and every failure lies within δ of one kept, so its size lies between the fewest
//!   δ-balls that cover the failures and the most δ-separated failures there are.
//!
//! Why test order: it is fixed by the run (no tie-breaking, no seed) and it makes the count
//! monotone along a run: a failure found later never changes whether an earlier one was kept, so
//! the count after k tests never falls as k grows, and a failure at least δ from all others always
//! adds exactly one wherever it comes. Inserting a failure within δ of others *before* them can
//! lower the count (it may shadow two failures that were δ apart); a greedy count cannot avoid
//! that, and a run only ever appends.

use crate::road::Point;

/// Road compared on each side of the exit, metres (the competition's OOB segment reach).
pub const REACH_M: f64 = crate::oob::segment::REACH_M;
/// Arc length between the chords of an exit profile, metres.
pub const STEP_M: f64 = 1.0;
/// Values of an exit profile: one chord per [`STEP_M`] from −[`REACH_M`] to +[`REACH_M`].
pub const PROFILE_LEN: usize = 2 * (REACH_M / STEP_M) as usize + 1;
/// Two failures whose exit profiles lie closer than this are the same failure, radians (RMS
/// heading difference): above nearly every distance between a failing road and a near-identical
/// copy of it driven again, and below the distance at which failures' bends into the exit differ
/// (docs/experiments/2026-11-25-distinct-failures.md).
pub const DELTA_RAD: f64 = 0.1;

/// The road around a lane exit: headings of 1 m chords relative to the chord at the exit.
#[derive(Debug, Clone, PartialEq)]
pub struct ExitProfile {
    /// [`PROFILE_LEN`] relative headings, radians, from 30 m before the exit to 30 m after.
    headings: Vec<f64>,
}

impl ExitProfile {
    /// The exit profile of the centre line `line` (the interpolated road, in driving order) for a
    /// car that left its lane at `exit`; `None` when `line` has no length or a coordinate is not
    /// finite.
    pub fn of(line: &[Point], exit: Point) -> Option<Self> {
        if !line.iter().chain([&exit]).flatten().all(|c| c.is_finite()) {
            return None;
        }
        let path = ArcLength::of(line)?;
        let at_exit = path.nearest(exit);
        // Chord k runs from offset k − 30.5 m to k − 29.5 m: centred on −30, ..., 30 m.
        let half = (PROFILE_LEN / 2) as f64;
        let points: Vec<Point> = (0..=PROFILE_LEN)
            .map(|k| path.point_at(at_exit + (k as f64 - half - 0.5) * STEP_M))
            .collect();
        let mut headings = Vec::with_capacity(PROFILE_LEN);
        let mut unwrapped = 0.0;
        let mut previous: Option<f64> = None;
        for w in points.windows(2) {
            let heading = (w[1][1] - w[0][1]).atan2(w[1][0] - w[0][0]);
            if let Some(previous) = previous {
                // A road never turns by half a revolution within a metre.
                let turn = heading - previous;
                unwrapped += turn - std::f64::consts::TAU * (turn / std::f64::consts::TAU).round();
            }
            previous = Some(heading);
            headings.push(unwrapped);
        }
        let at_exit = headings[PROFILE_LEN / 2];
        headings.iter_mut().for_each(|h| *h -= at_exit);
        Some(Self { headings })
    }

    /// The relative headings, radians, from 30 m before the exit to 30 m after.
    pub fn headings(&self) -> &[f64] {
        &self.headings
    }

    /// The root mean square difference of the two profiles' headings, radians.
    pub fn distance(&self, other: &Self) -> f64 {
        let sum: f64 = self
            .headings
            .iter()
            .zip(&other.headings)
            .map(|(a, b)| (a - b) * (a - b))
            .sum();
        (sum / PROFILE_LEN as f64).sqrt()
    }

    /// The centre line this profile describes, from 30 m before the exit to 30 m after, with the
    /// exit at the origin and the road heading north there (for pictures).
    pub fn outline(&self) -> Vec<Point> {
        let half = PROFILE_LEN / 2;
        let north = std::f64::consts::FRAC_PI_2;
        let step = |h: f64| [STEP_M * (north + h).cos(), STEP_M * (north + h).sin()];
        // The exit chord's midpoint is the origin; walk each way from its ends.
        let mut after = vec![step(self.headings[half]).map(|c| c / 2.0)];
        for &h in &self.headings[half + 1..] {
            let [x, y] = after[after.len() - 1];
            let [dx, dy] = step(h);
            after.push([x + dx, y + dy]);
        }
        let [dx, dy] = step(self.headings[half]);
        let mut before = vec![[-dx / 2.0, -dy / 2.0]];
        for &h in self.headings[..half].iter().rev() {
            let [x, y] = before[before.len() - 1];
            let [dx, dy] = step(h);
            before.push([x - dx, y - dy]);
        }
        before.reverse();
        before.extend(after);
        before
    }
}

/// The failures kept by the greedy count: indices into `profiles`, in order, of each profile at
/// least `delta` from every profile kept before it.
pub fn distinct(profiles: &[ExitProfile], delta: f64) -> Vec<usize> {
    let mut kept: Vec<usize> = Vec::new();
    for (i, profile) in profiles.iter().enumerate() {
        if kept.iter().all(|&k| apart(&profiles[k], profile, delta)) {
            kept.push(i);
        }
    }
    kept
}

/// `a.distance(b) >= delta`, without summing every difference when the first ones already put
/// the pair beyond `delta` (most pairs of different failures): the squares are summed in the
/// order [`ExitProfile::distance`] sums them, so a prefix never exceeds the whole, and the bound
/// has a margin far above rounding; a pair not decided so is measured in full.
fn apart(a: &ExitProfile, b: &ExitProfile, delta: f64) -> bool {
    let beyond = delta * delta * PROFILE_LEN as f64 * (1.0 + 1e-9);
    let mut sum = 0.0;
    for (i, (x, y)) in a.headings.iter().zip(&b.headings).enumerate() {
        sum += (x - y) * (x - y);
        if i % 8 == 7 && sum > beyond {
            return true;
        }
    }
    a.distance(b) >= delta
}

/// A polyline measured by arc length, extended straight past both ends.
struct ArcLength<'a> {
    /// The points.
    line: &'a [Point],
    /// Arc length at each point.
    at: Vec<f64>,
    /// Unit direction of the first and last segments of positive length.
    ends: (Point, Point),
}

impl<'a> ArcLength<'a> {
    /// `line` measured; `None` without positive length.
    fn of(line: &'a [Point]) -> Option<Self> {
        let mut at = Vec::with_capacity(line.len());
        let mut total = 0.0;
        at.push(0.0);
        for w in line.windows(2) {
            total += distance(w[0], w[1]);
            at.push(total);
        }
        let direction = |w: &[Point]| {
            let length = distance(w[0], w[1]);
            (length > 0.0).then(|| [(w[1][0] - w[0][0]) / length, (w[1][1] - w[0][1]) / length])
        };
        let first = line.windows(2).find_map(direction)?;
        let last = line.windows(2).rev().find_map(direction)?;
        Some(Self {
            line,
            at,
            ends: (first, last),
        })
    }

    /// Arc length of the point of the line nearest `p` (the first of equally near ones).
    fn nearest(&self, p: Point) -> f64 {
        let mut best = (f64::INFINITY, 0.0);
        for (i, w) in self.line.windows(2).enumerate() {
            let length = self.at[i + 1] - self.at[i];
            let t = if length > 0.0 {
                let along =
                    (p[0] - w[0][0]) * (w[1][0] - w[0][0]) + (p[1] - w[0][1]) * (w[1][1] - w[0][1]);
                (along / (length * length)).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let q = lerp(w[0], w[1], t);
            let d = distance(p, q);
            if d < best.0 {
                best = (d, self.at[i] + t * length);
            }
        }
        best.1
    }

    /// The point at arc length `s`, on the straight extensions before 0 and past the end.
    fn point_at(&self, s: f64) -> Point {
        let total = self.at[self.at.len() - 1];
        let along = |p: Point, d: Point, by: f64| [p[0] + by * d[0], p[1] + by * d[1]];
        if s <= 0.0 {
            return along(self.line[0], self.ends.0, s);
        }
        if s >= total {
            return along(self.line[self.line.len() - 1], self.ends.1, s - total);
        }
        // The segment [i, i + 1] holding s: at[i] <= s < at[i + 1].
        let i = self.at.partition_point(|&a| a <= s) - 1;
        let length = self.at[i + 1] - self.at[i];
        lerp(self.line[i], self.line[i + 1], (s - self.at[i]) / length)
    }
}

/// Euclidean distance of two points.
fn distance(a: Point, b: Point) -> f64 {
    (b[0] - a[0]).hypot(b[1] - a[1])
}

/// The point a share `t` of the way from `a` to `b`.
fn lerp(a: Point, b: Point, t: f64) -> Point {
    [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A road every metre: `straight_before` m north from (0, 0), then an arc of `radius` m
    /// (left when positive, right when negative) through `angle` radians, then 40 m straight.
    fn bend(straight_before: f64, radius: f64, angle: f64) -> Vec<Point> {
        let mut line = Vec::new();
        let mut heading = std::f64::consts::FRAC_PI_2;
        let mut p = [0.0, 0.0];
        line.push(p);
        let turn_per_m = 1.0 / radius;
        let arc_m = (angle * radius).abs();
        let mut go = |line: &mut Vec<Point>, metres: f64, turn: f64| {
            let steps = metres.round() as usize;
            for _ in 0..steps {
                heading += turn / 2.0;
                p = [p[0] + heading.cos(), p[1] + heading.sin()];
                heading += turn / 2.0;
                line.push(p);
            }
        };
        go(&mut line, straight_before, 0.0);
        go(&mut line, arc_m, turn_per_m);
        go(&mut line, 40.0, 0.0);
        line
    }

    /// The point of `line` `metres` along it (a point a metre).
    fn at(line: &[Point], metres: usize) -> Point {
        line[metres]
    }

    fn moved(line: &[Point], angle: f64, shift: Point) -> Vec<Point> {
        let (sin, cos) = angle.sin_cos();
        line.iter()
            .map(|p| {
                [
                    cos * p[0] - sin * p[1] + shift[0],
                    sin * p[0] + cos * p[1] + shift[1],
                ]
            })
            .collect()
    }

    fn mirrored(line: &[Point]) -> Vec<Point> {
        line.iter().map(|p| [-p[0], p[1]]).collect()
    }

    #[test]
    fn a_straight_road_has_a_flat_profile_of_60_metres() {
        let line: Vec<Point> = (0..=100).map(|i| [3.0, i as f64]).collect();
        let profile = ExitProfile::of(&line, [5.0, 50.0]).unwrap();
        assert_eq!(profile.headings().len(), PROFILE_LEN);
        assert_eq!(PROFILE_LEN, 61);
        assert!(profile.headings().iter().all(|h| h.abs() < 1e-12));
        let outline = profile.outline();
        assert_eq!(outline.len(), PROFILE_LEN + 1);
        assert!((outline[0][1] + 30.5).abs() < 1e-9 && (outline[61][1] - 30.5).abs() < 1e-9);
    }

    #[test]
    fn headings_are_relative_to_the_exit_and_turn_with_the_road() {
        // A left arc of radius 50 m through 90 degrees after 60 m of straight; exit mid-arc.
        let line = bend(60.0, 50.0, std::f64::consts::FRAC_PI_2);
        let exit = at(&line, 80);
        let profile = ExitProfile::of(&line, exit).unwrap();
        let h = profile.headings();
        assert_eq!(h[30], 0.0);
        // 10 m ahead on the arc: turned left by 10 / 50 rad; 10 m behind: 10 / 50 rad less.
        assert!((h[40] - 0.2).abs() < 0.01, "{}", h[40]);
        assert!((h[20] + 0.2).abs() < 0.01, "{}", h[20]);
        // 30 m behind the exit, 10 m before the arc: the straight, 20 m of arc back.
        assert!((h[0] + 0.4).abs() < 0.01, "{}", h[0]);
    }

    #[test]
    fn moving_or_turning_the_road_changes_nothing() {
        let line = bend(50.0, 40.0, 1.2);
        let exit = [at(&line, 70)[0] + 1.5, at(&line, 70)[1]];
        let profile = ExitProfile::of(&line, exit).unwrap();
        for (angle, shift) in [(0.0, [30.0, -7.0]), (2.5, [0.0, 0.0]), (-1.1, [80.0, 55.0])] {
            let other_line = moved(&line, angle, shift);
            let other_exit = moved(&[exit], angle, shift)[0];
            let other = ExitProfile::of(&other_line, other_exit).unwrap();
            assert!(profile.distance(&other) < 1e-9, "{angle} {shift:?}");
        }
    }

    #[test]
    fn a_mirrored_bend_is_another_failure() {
        let line = bend(50.0, 40.0, 1.2);
        let exit = at(&line, 70);
        let profile = ExitProfile::of(&line, exit).unwrap();
        let mirror = ExitProfile::of(&mirrored(&line), [-exit[0], exit[1]]).unwrap();
        let negated: Vec<f64> = profile.headings().iter().map(|h| -h).collect();
        assert!(mirror
            .headings()
            .iter()
            .zip(&negated)
            .all(|(a, b)| (a - b).abs() < 1e-9));
        assert!(profile.distance(&mirror) > 3.0 * DELTA_RAD);
    }

    #[test]
    fn road_far_from_the_exit_does_not_count() {
        // The same bend and exit, after 50 m or after 300 m of straight, and followed by another
        // bend 40 m on (out of reach) or not: one failure.
        let short = bend(50.0, 40.0, 1.0);
        let long = bend(300.0, 40.0, 1.0);
        let mut longer = long.clone();
        let [x, y] = longer[longer.len() - 1];
        longer.extend((1..=60).map(|i| [x - i as f64, y + 0.5 * i as f64]));
        let a = ExitProfile::of(&short, at(&short, 60)).unwrap();
        let b = ExitProfile::of(&long, at(&long, 310)).unwrap();
        let c = ExitProfile::of(&longer, at(&longer, 310)).unwrap();
        assert!(a.distance(&b) < 1e-9, "{}", a.distance(&b));
        assert!(a.distance(&c) < 1e-9, "{}", a.distance(&c));
    }

    #[test]
    fn a_window_past_the_road_goes_on_straight() {
        // An exit 10 m after the start: the 20 m before the road read as straight ahead, as on a
        // road that had 20 m more of straight before.
        let line = bend(20.0, 40.0, 1.0);
        let longer = bend(40.0, 40.0, 1.0);
        let a = ExitProfile::of(&line, at(&line, 10)).unwrap();
        let b = ExitProfile::of(&longer, at(&longer, 30)).unwrap();
        assert!(a.distance(&b) < 1e-9, "{}", a.distance(&b));
        // Past the end: a flat tail.
        let end = ExitProfile::of(&line, line[line.len() - 1]).unwrap();
        assert!(end.headings()[30..].iter().all(|h| h.abs() < 1e-9));
        assert_eq!(ExitProfile::of(&[[1.0, 1.0], [1.0, 1.0]], [0.0, 0.0]), None);
        assert_eq!(ExitProfile::of(&line, [f64::NAN, 3.0]), None);
        assert_eq!(
            ExitProfile::of(&[[0.0, 0.0], [0.0, f64::INFINITY]], [0.0, 1.0]),
            None
        );
    }

    #[test]
    fn the_distance_is_a_metric_in_radians() {
        let line = bend(50.0, 40.0, 1.2);
        let p: Vec<ExitProfile> = [55, 62, 70, 95]
            .iter()
            .map(|&m| ExitProfile::of(&line, at(&line, m)).unwrap())
            .collect();
        for a in &p {
            assert_eq!(a.distance(a), 0.0);
            for b in &p {
                assert!((a.distance(b) - b.distance(a)).abs() < 1e-12);
                for c in &p {
                    assert!(a.distance(c) <= a.distance(b) + b.distance(c) + 1e-12);
                }
            }
        }
        // A profile turned uniformly by 0.3 rad everywhere but the exit is about 0.3 away.
        let flat: Vec<Point> = (0..=100).map(|i| [0.0, i as f64]).collect();
        let flat = ExitProfile::of(&flat, [0.0, 50.0]).unwrap();
        let shifted = ExitProfile {
            headings: (0..PROFILE_LEN)
                .map(|k| if k == 30 { 0.0 } else { 0.3 })
                .collect(),
        };
        assert!((flat.distance(&shifted) - 0.3 * (60.0f64 / 61.0).sqrt()).abs() < 1e-12);
    }

    /// Profiles of the same left bend (radius 40 m) with exits 0.5 m apart, and of bends of other
    /// radii and the mirrored bend.
    fn profiles() -> (ExitProfile, ExitProfile, Vec<ExitProfile>) {
        let line = bend(50.0, 40.0, 1.2);
        let one = ExitProfile::of(&line, at(&line, 70)).unwrap();
        let again = ExitProfile::of(&line, [at(&line, 70)[0], at(&line, 70)[1] + 0.5]).unwrap();
        let others = [(15.0, 1.5), (-40.0, 1.2), (120.0, 0.6)]
            .iter()
            .map(|&(radius, angle)| {
                let line = bend(50.0, radius, angle);
                ExitProfile::of(&line, at(&line, 70)).unwrap()
            })
            .collect();
        (one, again, others)
    }

    #[test]
    fn identical_failures_count_once_and_far_ones_apart() {
        let (one, again, others) = profiles();
        assert!(one.distance(&again) < DELTA_RAD);
        assert_eq!(distinct(&[], DELTA_RAD), Vec::<usize>::new());
        assert_eq!(distinct(std::slice::from_ref(&one), DELTA_RAD), [0]);
        assert_eq!(distinct(&[one.clone(), one.clone()], DELTA_RAD), [0]);
        assert_eq!(distinct(&[one.clone(), again.clone()], DELTA_RAD), [0]);
        for other in &others {
            assert!(one.distance(other) >= DELTA_RAD, "{}", one.distance(other));
            assert_eq!(distinct(&[one.clone(), other.clone()], DELTA_RAD), [0, 1]);
        }
        let mut all = vec![one.clone(), again.clone()];
        all.extend(others.iter().cloned());
        assert_eq!(distinct(&all, DELTA_RAD), [0, 2, 3, 4]);
    }

    #[test]
    fn a_failure_far_from_all_adds_one_wherever_it_comes() {
        let (one, again, others) = profiles();
        let base = vec![one.clone(), again, others[0].clone(), others[1].clone()];
        let count = distinct(&base, DELTA_RAD).len();
        let far = others[2].clone();
        for at in 0..=base.len() {
            let mut with = base.clone();
            with.insert(at, far.clone());
            assert_eq!(
                distinct(&with, DELTA_RAD).len(),
                count + 1,
                "inserted at {at}"
            );
        }
        // Appending never lowers the count, whatever is appended.
        for extra in [one.clone(), far] {
            let mut with = base.clone();
            with.push(extra);
            assert!(distinct(&with, DELTA_RAD).len() >= count);
        }
    }

    #[test]
    fn the_count_follows_the_order_given() {
        // b lies within δ of a and of c, which are 2δ apart: a first keeps a and c, b first only b.
        let profile = |v: f64| ExitProfile {
            headings: vec![v; PROFILE_LEN],
        };
        let (a, b, c) = (
            profile(0.0),
            profile(0.8 * DELTA_RAD),
            profile(1.6 * DELTA_RAD),
        );
        assert_eq!(
            distinct(&[a.clone(), b.clone(), c.clone()], DELTA_RAD),
            [0, 2]
        );
        assert_eq!(distinct(&[b, a, c], DELTA_RAD), [0]);
    }

    #[test]
    fn the_early_answer_is_the_full_distances_answer() {
        // Pairs at every distance around δ, their differences spread unevenly along the profile.
        let mut seed = 0x2545_F491_4F6C_DD1Du64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for pair in 0..20_000 {
            let scale = DELTA_RAD * 2.0 * (pair as f64 / 20_000.0);
            let a = ExitProfile {
                headings: (0..PROFILE_LEN).map(|_| next()).collect(),
            };
            let weights: Vec<f64> = (0..PROFILE_LEN).map(|_| next().powi(4)).collect();
            let norm = (weights.iter().map(|w| w * w).sum::<f64>() / PROFILE_LEN as f64).sqrt();
            let b = ExitProfile {
                headings: a
                    .headings
                    .iter()
                    .zip(&weights)
                    .map(|(h, w)| h + scale * w / norm)
                    .collect(),
            };
            assert_eq!(
                apart(&a, &b, DELTA_RAD),
                a.distance(&b) >= DELTA_RAD,
                "pair {pair}"
            );
        }
        let same = ExitProfile {
            headings: vec![0.3; PROFILE_LEN],
        };
        assert!(!apart(&same, &same.clone(), DELTA_RAD));
    }
}
