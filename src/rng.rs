//! The seeded random numbers of a run: `rand_xoshiro`'s xoshiro256** seeded by SplitMix64
//! (`SeedableRng::seed_from_u64`), uniform numbers from `rand`'s standard distribution and
//! normal ones from `rand_distr`'s: the same seed gives the same sequence on every machine,
//! so runs are reproducible. One type, so every layer draws the same way.

use rand::{Rng, RngExt, SeedableRng};
use rand_distr::{Distribution, StandardNormal};
use rand_xoshiro::Xoshiro256StarStar;

/// A small, fast, seedable generator.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SimRng(Xoshiro256StarStar);

impl SimRng {
    /// A stream seeded with `seed`.
    pub fn new(seed: u64) -> Self {
        SimRng(Xoshiro256StarStar::seed_from_u64(seed))
    }

    /// A generator for a sub-stream (robot `i`, module `j`): independent of the others.
    pub fn fork(&mut self, stream: u64) -> SimRng {
        SimRng::new(self.next_u64() ^ stream.wrapping_mul(0xD1B5_4A32_D192_ED03))
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0.next_u64()
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        self.0.random::<f64>()
    }

    /// Uniform in [lo, hi) (`lo` when the interval is empty; never a panic).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }

    /// Standard normal.
    pub fn gaussian(&mut self) -> f64 {
        StandardNormal.sample(&mut self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stream_is_xoshiro256_starstar_seeded_by_splitmix64() {
        // The first outputs for seed 0, as the generator's reference implementation gives
        // them (what the hand-written generator this replaced produced too).
        let mut r = SimRng::new(0);
        let first: Vec<u64> = (0..3).map(|_| r.next_u64()).collect();
        assert_eq!(
            first,
            [
                0x99EC_5F36_CB75_F2B4,
                0xBF6E_1F78_4956_452A,
                0x1A5F_849D_4933_E6E0
            ]
        );
    }

    #[test]
    fn same_seed_same_sequence_other_seed_other_sequence() {
        let a: Vec<u64> = (0..5)
            .scan(SimRng::new(7), |r, _| Some(r.next_u64()))
            .collect();
        let b: Vec<u64> = (0..5)
            .scan(SimRng::new(7), |r, _| Some(r.next_u64()))
            .collect();
        let c: Vec<u64> = (0..5)
            .scan(SimRng::new(8), |r, _| Some(r.next_u64()))
            .collect();
        assert_eq!(a, b);
        assert_ne!(a, c);
    }

    #[test]
    fn gaussian_has_unit_variance() {
        let mut r = SimRng::new(1);
        let n = 20_000;
        let xs: Vec<f64> = (0..n).map(|_| r.gaussian()).collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
        assert!(
            mean.abs() < 0.03 && (var - 1.0).abs() < 0.05,
            "{mean} {var}"
        );
    }
}
