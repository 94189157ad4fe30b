//! Counter-based randomness: every random number is a pure function of (seed, purpose,
//! integer coordinates), so results do not depend on evaluation order, threads or tiling.

/// The 64-bit finaliser of MurmurHash3 (`fmix64`): a bijection with full avalanche.
#[inline(always)]
pub fn mix64(mut z: u64) -> u64 {
    z ^= z >> 33;
    z = z.wrapping_mul(0xff51_afd7_ed55_8ccd);
    z ^= z >> 33;
    z = z.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
    z ^ (z >> 33)
}

/// Odd constants decorrelating the axes before mixing.
const AXIS: [u64; 4] = [0x9e37_79b9_7f4a_7c15, 0xc2b2_ae3d_27d4_eb4f, 0x1656_67b1_9e37_79f9, 0x27d4_eb2f_1656_67c5];

/// Hash of a seed and up to four integer coordinates.
#[inline(always)]
pub fn hash_coords(seed: u64, coords: &[i64]) -> u64 {
    let mut h = seed;
    for (axis, &c) in AXIS.iter().zip(coords) {
        h = mix64(h ^ (c as u64).wrapping_mul(*axis));
    }
    h
}

/// A seed for one purpose (gradients, impulses, terrain level ...) derived from a user seed.
pub fn derive_seed(seed: u64, purpose: &str) -> u64 {
    purpose.bytes().fold(mix64(seed ^ 0x5bd1_e995), |h, b| mix64(h ^ u64::from(b)))
}

/// A small counter-based stream (SplitMix64) for drawing several numbers from one hash.
#[derive(Debug, Clone)]
pub struct Stream {
    state: u64,
}

impl Stream {
    /// A stream starting from a hash.
    pub fn new(hash: u64) -> Self {
        Stream { state: hash }
    }

    /// The next 64 random bits.
    #[inline(always)]
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        mix64(self.state)
    }

    /// Uniform in [0, 1) with 53 bits.
    #[inline(always)]
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in [lo, hi).
    #[inline(always)]
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Poisson-distributed count with the given mean (Knuth's product of uniforms, in
    /// chunks of `POISSON_CHUNK`).
    pub fn poisson(&mut self, mean: f64) -> u32 {
        // Knuth's product stops where e^(−mean) underflows (a mean near 745), which capped
        // large counts silently (#36): a larger mean is drawn as a sum of Poisson counts of
        // at most POISSON_CHUNK each (a sum of independent Poisson variables is Poisson),
        // and a mean up to it draws exactly as before.
        let mut mean = mean;
        let mut count = 0;
        while mean > POISSON_CHUNK {
            count += self.poisson_at_most_chunk(POISSON_CHUNK);
            mean -= POISSON_CHUNK;
        }
        count + self.poisson_at_most_chunk(mean)
    }

    /// Knuth's multiplication method, for a mean up to [`POISSON_CHUNK`].
    fn poisson_at_most_chunk(&mut self, mean: f64) -> u32 {
        let limit = (-mean).exp();
        let mut product = self.unit();
        let mut count = 0;
        while product > limit {
            count += 1;
            product *= self.unit();
        }
        count
    }
}

/// The largest mean [`Stream::poisson`] draws in one product: e^(−500) is far from
/// underflow (about 1e−217), so no product stops early.
const POISSON_CHUNK: f64 = 500.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn large_poisson_means_are_honoured() {
        // #36: Knuth's product underflowed near a mean of 745, capping larger counts.
        let mut rng = Stream::new(7);
        for mean in [20.0, 900.0, 5000.0] {
            let draws = 400;
            let total: f64 = (0..draws).map(|_| f64::from(rng.poisson(mean))).sum();
            let average = total / draws as f64;
            // Six standard errors of the average.
            let margin = 6.0 * (mean / draws as f64).sqrt();
            assert!((average - mean).abs() < margin, "mean {mean}: average {average}");
        }
    }
}
