//! Step timing: per-step wall times reduced to the median and mean.

/// Wall-clock cost of a run's steps, in milliseconds.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StepTiming {
    /// Median over steps: robust to the first steps' warm-up and to the odd preemption.
    pub median_ms: f64,
    /// Mean over steps.
    pub mean_ms: f64,
    /// Slowest step.
    pub max_ms: f64,
}

impl StepTiming {
    /// Summarizes per-step times (milliseconds).
    pub fn from_samples(samples: &[f64]) -> Self {
        if samples.is_empty() {
            return Self::default();
        }
        Self {
            median_ms: median(samples),
            mean_ms: samples.iter().sum::<f64>() / samples.len() as f64,
            max_ms: samples.iter().copied().fold(0.0, f64::max),
        }
    }
}

/// Median of `samples` (the mean of the two middle values for an even count); 0 when empty.
pub fn median(samples: &[f64]) -> f64 {
    if samples.is_empty() {
        return 0.0;
    }
    let mut sorted = samples.to_vec();
    sorted.sort_by(f64::total_cmp);
    let mid = sorted.len() / 2;
    if sorted.len() % 2 == 1 {
        sorted[mid]
    } else {
        0.5 * (sorted[mid - 1] + sorted[mid])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_ignores_a_single_slow_first_step() {
        let t = StepTiming::from_samples(&[50.0, 1.0, 1.2, 0.9, 1.1]);
        assert_eq!(t.median_ms, 1.1);
        assert_eq!(t.max_ms, 50.0);
        assert!((t.mean_ms - 54.2 / 5.0).abs() < 1e-12);
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), 2.5);
        assert_eq!(StepTiming::from_samples(&[]), StepTiming::default());
    }
}
