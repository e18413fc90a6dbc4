//! Numbers in reports, rounded to significant digits so files stay readable and diffable.

use serde_json::Value;

/// `v` rounded to `digits` significant digits; zero and non-finite values pass unchanged.
pub fn round_sig(v: f64, digits: i32) -> f64 {
    if v == 0.0 || !v.is_finite() {
        return v;
    }
    let shift = digits - v.abs().log10().ceil() as i32;
    let scale = 10f64.powi(shift.clamp(-300, 300));
    (v * scale).round() / scale
}

/// `v` rounded to `decimals` decimal places. Dividing the rounded integer by an exact power of
/// ten gives the double nearest that decimal, so Rust's shortest round-trip `{}` prints it
/// with no float noise (0.3, not 0.30000000000000004). Values beyond 2^53 / 10^decimals and
/// non-finite values pass unchanged.
pub fn snap_decimals(v: f64, decimals: i32) -> f64 {
    let scale = 10f64.powi(decimals);
    let scaled = v * scale;
    if !scaled.is_finite() || scaled.abs() >= 9.0e15 {
        return v;
    }
    scaled.round() / scale
}

/// `v` to 6 significant digits as JSON; a non-finite value (an infinite PSNR) is `null`.
pub fn json6(v: f64) -> Value {
    if v.is_finite() {
        Value::from(round_sig(v, 6))
    } else {
        Value::Null
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn snapped_decimals_print_without_noise() {
        assert_eq!(format!("{}", snap_decimals(0.1 + 0.2, 9)), "0.3");
        assert_eq!(format!("{}", snap_decimals(3.0 * 0.2, 9)), "0.6");
        assert_eq!(format!("{}", snap_decimals(-2856.05, 9)), "-2856.05");
        assert_eq!(snap_decimals(f64::INFINITY, 9), f64::INFINITY);
    }

    #[test]
    fn rounds_to_significant_digits_at_any_scale() {
        assert_eq!(round_sig(123_456_789.0, 3), 123_000_000.0);
        assert_eq!(round_sig(0.000_123_456, 2), 0.000_12);
        assert_eq!(round_sig(-2.345_678, 3), -2.35);
        assert_eq!(round_sig(0.0, 6), 0.0);
        assert!(round_sig(f64::NAN, 6).is_nan());
        assert_eq!(json6(1.0 / 3.0), Value::from(0.333_333));
        assert_eq!(json6(f64::INFINITY), Value::Null);
    }
}
