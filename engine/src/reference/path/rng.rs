//! The path tracer's random numbers.

use glam::Vec2;

/// A small, fast generator (PCG-RXS-M-XS 32, O'Neill 2014) seeded per pixel and sample so
/// that images are deterministic whatever the thread schedule.
pub struct Rng(u32);

impl Rng {
    /// A generator for sample `sample` of pixel `pixel` under `seed`: the three are mixed
    /// with the SplitMix64 finalizer (Steele et al. 2014), so neighbouring pixels and
    /// samples start from unrelated states.
    pub fn new(seed: u64, pixel: u32, sample: u32) -> Rng {
        let mut z = seed
            .wrapping_mul(0x9e37_79b9_7f4a_7c15)
            .wrapping_add((u64::from(pixel) << 32) | u64::from(sample));
        for _ in 0..2 {
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^= z >> 31;
        }
        let mut rng = Rng((z ^ (z >> 32)) as u32);
        rng.next_u32();
        rng
    }

    /// A uniform u32.
    pub fn next_u32(&mut self) -> u32 {
        let state = self.0;
        self.0 = state.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
        let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
        (word >> 22) ^ word
    }

    /// A uniform f32 in [0, 1).
    pub fn uniform(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 / (1u32 << 24) as f32
    }

    /// Two uniform numbers.
    pub fn pair(&mut self) -> Vec2 {
        Vec2::new(self.uniform(), self.uniform())
    }
}
