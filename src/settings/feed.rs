//! The feed the part was cut with (mm/min): it turns a servo lag measured in mm of tool-tip path
//! into the position loop's time constant (`1/Kv = lag / feed`, effects.md "Shapes are
//! families"). The default is the feed of the finishing programme this tool writes.

/// The finishing programme's feed (mm/min), the default of an analysis's `feed`.
pub const PROGRAMME_FEED: f64 = 1000.0;

/// A time lag (ms) from a lag in mm of tool-tip path at `feed` mm/min: `1000·60·l/F`.
pub fn lag_ms(lag_mm: f64, feed: f64) -> f64 {
    60_000.0 * lag_mm / feed
}

#[cfg(test)]
mod tests {
    use super::*;

    /// servo_signatures.csv `sim_a`: C at Kv 30 against 40 1/s at 1500 mm/min trails by
    /// l = (1/30 − 1/40)·1500/60 = 0.208333 mm, i.e. 1/30 − 1/40 s = 8.333 ms.
    #[test]
    fn a_path_lag_is_a_time_constant_at_the_feed() {
        assert!((lag_ms(0.208_333_333_333, 1500.0) - 8.333_333).abs() < 1e-5);
    }
}
