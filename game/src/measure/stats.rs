//! Summary statistics of a series of timings.

use serde_json::{Value, json};

/// Mean, median, tail percentiles, extremes and spread of a series (same unit as the
/// values, ms in every bench report).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Summary {
    /// Number of values.
    pub n: usize,
    /// Arithmetic mean.
    pub mean: f64,
    /// 50th percentile.
    pub median: f64,
    /// 95th percentile.
    pub p95: f64,
    /// 99th percentile.
    pub p99: f64,
    /// Smallest value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
    /// Sample standard deviation (n − 1 in the denominator; 0 for one value).
    pub std: f64,
}

/// The `p`-th quantile (0..=1) of sorted `values`, interpolating linearly between the two
/// closest ranks (Hyndman & Fan's definition 7, numpy's default).
pub fn quantile(sorted: &[f64], p: f64) -> Option<f64> {
    let last = sorted.len().checked_sub(1)?;
    let h = last as f64 * p.clamp(0.0, 1.0);
    let lo = h.floor() as usize;
    let hi = (lo + 1).min(last);
    Some(sorted[lo] + (h - lo as f64) * (sorted[hi] - sorted[lo]))
}

impl Summary {
    /// The summary of `values`; `None` if there are none or any is not finite.
    pub fn of(values: &[f64]) -> Option<Summary> {
        if values.is_empty() || values.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let mut sorted = values.to_vec();
        sorted.sort_by(f64::total_cmp);
        let n = values.len();
        let mean = values.iter().sum::<f64>() / n as f64;
        let var = if n > 1 {
            values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64
        } else {
            0.0
        };
        Some(Summary {
            n,
            mean,
            median: quantile(&sorted, 0.5)?,
            p95: quantile(&sorted, 0.95)?,
            p99: quantile(&sorted, 0.99)?,
            min: sorted[0],
            max: sorted[n - 1],
            std: var.sqrt(),
        })
    }

    /// The JSON object of the report schema.
    pub fn to_json(&self) -> Value {
        json!({
            "n": self.n, "mean": self.mean, "median": self.median, "p95": self.p95,
            "p99": self.p99, "min": self.min, "max": self.max, "std": self.std,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_values() {
        let s = Summary::of(&[4.0, 1.0, 3.0, 2.0, 5.0]).expect("summary");
        assert_eq!(
            (s.n, s.min, s.max, s.median, s.mean),
            (5, 1.0, 5.0, 3.0, 3.0)
        );
        // Linear interpolation: h = 4 · 0.95 = 3.8 → 4 + 0.8 · (5 − 4).
        assert!((s.p95 - 4.8).abs() < 1e-12 && (s.p99 - 4.96).abs() < 1e-12);
        // Sample standard deviation of 1..5: √2.5.
        assert!((s.std - 2.5f64.sqrt()).abs() < 1e-12);
        let one = Summary::of(&[7.0]).expect("summary");
        assert_eq!((one.median, one.p99, one.std), (7.0, 7.0, 0.0));
        assert_eq!(Summary::of(&[]), None);
        assert_eq!(Summary::of(&[1.0, f64::NAN]), None);
        assert_eq!(quantile(&[1.0, 2.0], 0.5), Some(1.5));
    }
}
