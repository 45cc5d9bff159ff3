//! Option values inside, at and beyond their ranges, non-finite, overflowing and garbage.

use super::*;

/// One of `items`.
pub(super) fn pick<'a, T>(rng: &mut ChaCha8Rng, items: &'a [T]) -> &'a T {
    items.choose(rng).expect("a choice from a non-empty list")
}

/// True with probability `p`.
pub(super) fn chance(rng: &mut ChaCha8Rng, p: f64) -> bool {
    rng.random_bool(p)
}

/// Numbers no option takes, or takes only at its edge: signs, non-finite values, overflow,
/// underflow and integers beyond every integer type.
pub(super) const WILD_NUMBERS: [&str; 20] = [
    "0",
    "-0",
    "-1",
    "NaN",
    "nan",
    "-nan",
    "inf",
    "-inf",
    "infinity",
    "1e308",
    "-1e308",
    "1e309",
    "1.7976931348623157e308",
    "5e-324",
    "1e-300",
    "1e-400",
    "18446744073709551615",
    "18446744073709551616",
    "-9223372036854775809",
    "340282366920938463463374607431768211456",
];
/// Text that is no number, or only nearly one.
pub(super) const GARBAGE: [&str; 12] = [
    "", " ", "abc", "1,5", "0x10", " 1", "1_000", "1e", "--1", "\u{bd}", "1.2.3", "+-1",
];
/// Integers beyond the ranges of `u32`, `u64` and `i64`, and numbers that are not integers.
pub(super) const WILD_INTEGERS: [&str; 11] = [
    "4294967295",
    "4294967296",
    "18446744073709551615",
    "18446744073709551616",
    "-9223372036854775809",
    "99999999999999999999999999",
    "1e3",
    "1.5",
    "+3",
    "007",
    "-0",
];
/// Names no option takes.
pub(super) const WRONG_NAMES: [&str; 8] = [
    "",
    "DAVE2-PROXY",
    "beamng",
    "Bolp",
    "wogan ",
    "random,wogan",
    "sbst2",
    "-",
];

/// A floating-point option's value: within `typical`; or (wild) also at and just beyond the
/// valid range `lo..=hi`, non-finite, huge, tiny or garbage. Even a wild case keeps most values
/// valid, so that a few edge values together get past the parser.
pub(super) fn float_arg(
    rng: &mut ChaCha8Rng,
    wild: bool,
    lo: f64,
    hi: f64,
    typical: (f64, f64),
) -> String {
    let inside = |rng: &mut ChaCha8Rng| rng.random_range(typical.0..=typical.1).to_string();
    if !wild {
        return inside(rng);
    }
    match rng.random_range(0..8) {
        0..=2 => inside(rng),
        3 | 4 => {
            let edges = [
                lo,
                lo.next_down(),
                lo.next_up(),
                -lo - 1.0,
                hi,
                hi.next_up(),
                hi.next_down(),
                hi * 2.0,
                hi * 1e6,
            ];
            format!("{:?}", pick(rng, &edges))
        }
        5 | 6 => pick(rng, &WILD_NUMBERS).to_string(),
        _ => pick(rng, &GARBAGE).to_string(),
    }
}

/// An integer option's value: within `typical`; or (wild) also at and beyond `lo..=hi`, beyond
/// every integer type, not an integer, or garbage.
pub(super) fn int_arg(
    rng: &mut ChaCha8Rng,
    wild: bool,
    lo: i128,
    hi: i128,
    typical: (i64, i64),
) -> String {
    let inside = |rng: &mut ChaCha8Rng| rng.random_range(typical.0..=typical.1).to_string();
    if !wild {
        return inside(rng);
    }
    match rng.random_range(0..8) {
        0..=2 => inside(rng),
        3 | 4 => pick(rng, &[lo - 1, lo, hi, hi + 1, 0, -1]).to_string(),
        5 | 6 => pick(rng, &WILD_INTEGERS).to_string(),
        _ => pick(rng, &GARBAGE).to_string(),
    }
}

/// One of `valid`, or (wild, now and then) a name no option takes.
pub(super) fn name_arg(rng: &mut ChaCha8Rng, wild: bool, valid: &[&str]) -> String {
    if wild && chance(rng, 0.3) {
        pick(rng, &WRONG_NAMES).to_string()
    } else {
        pick(rng, valid).to_string()
    }
}
