//! Angle helpers shared by the sensor and read-out models.
//!
//! Angular position information lives in one rotation, `[0, 360)` deg
//! ([0105], [0107]); the key-on tracking of [0115] accumulates angle changes
//! wrapped into `(-180, 180]` deg; the θ1/θ2 diagnosis of [0118] compares two
//! angular positions on the circle.

/// Wraps `deg` into `[0, 360)`.
///
/// Unlike a bare `rem_euclid`, this never returns `360.0` (which
/// `(-1e-20_f64).rem_euclid(360.0)` does because of rounding).
/// Non-finite input is returned as NaN.
pub fn wrap_360(deg: f64) -> f64 {
    if !deg.is_finite() {
        return f64::NAN;
    }
    let r = deg.rem_euclid(360.0);
    if r >= 360.0 {
        0.0
    } else {
        r
    }
}

/// Wraps `deg` into `(-180, 180]`.
///
/// Non-finite input is returned as NaN.
pub fn wrap_180(deg: f64) -> f64 {
    let r = wrap_360(deg);
    if r > 180.0 {
        r - 360.0
    } else {
        r
    }
}

/// Circular distance between two angles, in `[0, 180]` deg ([0118]).
pub fn circular_diff_deg(a_deg: f64, b_deg: f64) -> f64 {
    wrap_180(a_deg - b_deg).abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_360_never_returns_360() {
        assert_eq!(wrap_360(-1e-20), 0.0);
        assert_eq!(wrap_360(360.0), 0.0);
        assert_eq!(wrap_360(-90.0), 270.0);
        assert_eq!(wrap_360(725.0), 5.0);
        assert!(wrap_360(f64::NAN).is_nan());
    }

    #[test]
    fn wrap_180_half_open_interval() {
        assert_eq!(wrap_180(180.0), 180.0);
        assert_eq!(wrap_180(-180.0), 180.0);
        assert_eq!(wrap_180(181.0), -179.0);
        assert_eq!(wrap_180(-2.0), -2.0);
        assert_eq!(wrap_180(1.0 - 359.0), 2.0);
    }

    #[test]
    fn circular_diff_across_zero() {
        assert!((circular_diff_deg(359.0, 1.0) - 2.0).abs() < 1e-12);
        assert!((circular_diff_deg(1.0, 359.0) - 2.0).abs() < 1e-12);
        assert_eq!(circular_diff_deg(0.0, 180.0), 180.0);
    }
}
