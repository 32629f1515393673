//! One episode as the writer and its backends (Arrow, HDF5) take it. Its own module so the
//! backends depend on the episode, not on the writer that calls them.

/// One info key: `width` values per row, `values` row-major over T+1 rows.
#[derive(Clone, Debug, Default)]
pub struct InfoColumn {
    /// The info key.
    pub key: String,
    /// Values per row.
    pub width: usize,
    /// The values, row-major.
    pub values: Vec<f64>,
}

/// One episode to write. `observations` has T+1 rows of `obs_dim`, `actions` T rows of `act_dim`.
#[derive(Clone, Copy, Debug)]
pub struct EpisodeRecord<'a> {
    /// The reset seed (None: the episode continued the RNG stream).
    pub seed: Option<u64>,
    /// T+1 observations, flat.
    pub observations: &'a [f64],
    /// T actions, flat.
    pub actions: &'a [f32],
    /// T rewards.
    pub rewards: &'a [f64],
    /// T terminated flags.
    pub terminations: &'a [bool],
    /// T truncated flags.
    pub truncations: &'a [bool],
    /// The info keys' columns.
    pub infos: &'a [InfoColumn],
}

impl EpisodeRecord<'_> {
    /// T, the number of steps.
    pub fn steps(&self) -> usize {
        self.rewards.len()
    }
    /// `rewards_sum, _mean, _std, _max, _min`, as Minari's default `EpisodeMetadataCallback`.
    pub fn reward_stats(&self) -> [(&'static str, f64); 5] {
        let r = self.rewards;
        let n = r.len().max(1) as f64;
        let sum: f64 = r.iter().sum();
        let mean = sum / n;
        let var = r.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / n;
        let max = r.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let min = r.iter().copied().fold(f64::INFINITY, f64::min);
        [
            ("rewards_sum", sum),
            ("rewards_mean", mean),
            ("rewards_std", var.sqrt()),
            ("rewards_max", max),
            ("rewards_min", min),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reward_stats_are_numpys_with_the_population_std() {
        let rewards = [1.0, 2.0, 3.0, 4.0];
        let r = EpisodeRecord {
            seed: None,
            observations: &[],
            actions: &[],
            rewards: &rewards,
            terminations: &[false; 4],
            truncations: &[false; 4],
            infos: &[],
        };
        assert_eq!(r.steps(), 4);
        // numpy: sum, mean, std (ddof=0), max, min of [1, 2, 3, 4].
        let want = [10.0, 2.5, 1.25f64.sqrt(), 4.0, 1.0];
        let names = [
            "rewards_sum",
            "rewards_mean",
            "rewards_std",
            "rewards_max",
            "rewards_min",
        ];
        for ((name, got), (n, w)) in r.reward_stats().into_iter().zip(names.iter().zip(want)) {
            assert_eq!((name, got), (*n, w));
        }
    }
}
