//! Sample points in the unit cube, addressable by index: point i of a run is the same whatever
//! the thread count, the chunking or the shard that computes it, so a run is reproducible to
//! the byte from its seed alone.
//!
//! * [`Sampler::Sobol`]: the Sobol sequence (Joe & Kuo's direction numbers, `new-joe-kuo-6`,
//!   criterion D(6)) randomised by a digital shift drawn from the seed: each coordinate is XORed
//!   with a fixed random 32-bit word. The shift keeps the net structure (every 2^m consecutive
//!   points from index 0 stratify the cube as the unshifted ones do) and makes each point
//!   uniform on the cube, so estimates are unbiased and independent seeds give an error estimate.
//! * [`Sampler::Random`]: independent uniform points (SplitMix64 of seed, index and coordinate).

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// Joe & Kuo's primitive polynomials and initial direction numbers, dimensions 2 … 32 (the first
/// dimension is the van der Corput sequence): (degree s, coefficients a, m_1 … m_s). Data from
/// S. Joe and F. Y. Kuo, "Constructing Sobol sequences with better two-dimensional projections",
/// SIAM J. Sci. Comput. 30 (2008) 2635–2654, file new-joe-kuo-6.21201 (BSD licence).
const JOE_KUO: [(u32, u32, &[u32]); 31] = [
    (1, 0, &[1]),
    (2, 1, &[1, 3]),
    (3, 1, &[1, 3, 1]),
    (3, 2, &[1, 1, 1]),
    (4, 1, &[1, 1, 3, 3]),
    (4, 4, &[1, 3, 5, 13]),
    (5, 2, &[1, 1, 5, 5, 17]),
    (5, 4, &[1, 1, 5, 5, 5]),
    (5, 7, &[1, 1, 7, 11, 19]),
    (5, 11, &[1, 1, 5, 1, 1]),
    (5, 13, &[1, 1, 1, 3, 11]),
    (5, 14, &[1, 3, 5, 5, 31]),
    (6, 1, &[1, 3, 3, 9, 7, 49]),
    (6, 13, &[1, 1, 1, 15, 21, 21]),
    (6, 16, &[1, 3, 1, 13, 27, 49]),
    (6, 19, &[1, 1, 1, 15, 7, 5]),
    (6, 22, &[1, 3, 1, 15, 13, 25]),
    (6, 25, &[1, 1, 5, 5, 19, 61]),
    (7, 1, &[1, 3, 7, 11, 23, 15, 103]),
    (7, 4, &[1, 3, 7, 13, 13, 15, 69]),
    (7, 7, &[1, 1, 3, 13, 7, 35, 63]),
    (7, 8, &[1, 3, 5, 9, 1, 25, 53]),
    (7, 14, &[1, 3, 1, 13, 9, 35, 107]),
    (7, 19, &[1, 3, 1, 5, 27, 61, 31]),
    (7, 21, &[1, 1, 5, 11, 19, 41, 61]),
    (7, 28, &[1, 3, 5, 3, 3, 13, 69]),
    (7, 31, &[1, 1, 7, 13, 1, 19, 1]),
    (7, 32, &[1, 3, 7, 5, 13, 19, 59]),
    (7, 37, &[1, 1, 3, 9, 25, 29, 41]),
    (7, 41, &[1, 3, 5, 13, 23, 1, 55]),
    (7, 42, &[1, 3, 7, 3, 13, 59, 17]),
];

/// Coordinates the Sobol sampler offers (a Saltelli design of k parameters needs 2k).
pub const MAX_DIMENSIONS: usize = JOE_KUO.len() + 1;

/// Bits of each coordinate (and the largest index + 1 is 2^BITS).
const BITS: usize = 32;

/// How the points are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum Sampler {
    /// Digitally shifted Sobol points (quasi-Monte Carlo).
    Sobol,
    /// Independent uniform points (Monte Carlo).
    Random,
}

impl Sampler {
    /// Both, in the order `--sampler` lists them.
    pub const ALL: [Sampler; 2] = [Sampler::Sobol, Sampler::Random];

    /// The name users write.
    pub fn name(self) -> &'static str {
        match self {
            Sampler::Sobol => "sobol",
            Sampler::Random => "random",
        }
    }
}

impl std::str::FromStr for Sampler {
    type Err = Error;
    fn from_str(s: &str) -> Result<Sampler> {
        crate::error::by_name(&Sampler::ALL, Sampler::name, "sampler", s)
    }
}

/// Points of one sampler and seed in `dims` coordinates.
#[derive(Clone, Debug)]
pub struct Points {
    sampler: Sampler,
    seed: u64,
    /// Direction numbers v[d][k] (Sobol only), and each coordinate's shift.
    directions: Vec<[u32; BITS]>,
    shifts: Vec<u32>,
}

/// SplitMix64: a well-mixed 64-bit hash of a counter.
pub(crate) fn splitmix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A uniform number in (0, 1) from a 64-bit word (53 bits, never 0 or 1).
pub(crate) fn unit53(w: u64) -> f64 {
    ((w >> 11) as f64 + 0.5) / (1u64 << 53) as f64
}

fn directions(dim: usize) -> [u32; BITS] {
    let mut v = [0u32; BITS];
    if dim == 0 {
        for (k, vk) in v.iter_mut().enumerate() {
            *vk = 1 << (BITS - 1 - k);
        }
        return v;
    }
    let (s, a, m) = JOE_KUO[dim - 1];
    let s = s as usize;
    for k in 0..BITS {
        v[k] = if k < s {
            m[k] << (BITS - 1 - k)
        } else {
            // v_k = a_1 v_{k−1} ⊕ … ⊕ a_{s−1} v_{k−s+1} ⊕ v_{k−s} ⊕ (v_{k−s} >> s)
            let mut x = v[k - s] ^ (v[k - s] >> s);
            for j in 1..s {
                if (a >> (s - 1 - j)) & 1 == 1 {
                    x ^= v[k - j];
                }
            }
            x
        };
    }
    v
}

impl Points {
    /// The points of `sampler` with `seed` in `dims` coordinates; Sobol offers at most
    /// [`MAX_DIMENSIONS`].
    pub fn new(sampler: Sampler, seed: u64, dims: usize) -> Result<Points> {
        if sampler == Sampler::Sobol && dims > MAX_DIMENSIONS {
            return Err(Error::InvalidInput {
                what: "sample dimension",
                text: dims.to_string(),
                reason: format!("the Sobol sampler has {MAX_DIMENSIONS} coordinates"),
            });
        }
        let directions = match sampler {
            Sampler::Sobol => (0..dims).map(directions).collect(),
            Sampler::Random => Vec::new(),
        };
        let shifts = (0..dims)
            .map(|d| (splitmix(seed ^ splitmix(d as u64 + 1)) >> 32) as u32)
            .collect();
        Ok(Points {
            sampler,
            seed,
            directions,
            shifts,
        })
    }

    /// Coordinates per point.
    pub fn dims(&self) -> usize {
        self.shifts.len()
    }

    /// Largest index + 1 (2^32 for Sobol).
    pub fn capacity(&self) -> u64 {
        match self.sampler {
            Sampler::Sobol => 1 << BITS,
            Sampler::Random => u64::MAX,
        }
    }

    /// Coordinate `d` of point `i`, in (0, 1).
    pub fn coordinate(&self, i: u64, d: usize) -> f64 {
        match self.sampler {
            Sampler::Sobol => {
                let v = &self.directions[d];
                let mut x = 0u32;
                let mut bits = i;
                let mut k = 0;
                while bits != 0 {
                    if bits & 1 == 1 {
                        x ^= v[k];
                    }
                    bits >>= 1;
                    k += 1;
                }
                ((x ^ self.shifts[d]) as f64 + 0.5) / (1u64 << BITS) as f64
            }
            Sampler::Random => {
                let w = splitmix(self.seed ^ splitmix(i.wrapping_mul(0x1_0000_0001) ^ d as u64));
                unit53(splitmix(w))
            }
        }
    }

    /// Point `i`, into `out` (length [`Points::dims`]).
    pub fn point(&self, i: u64, out: &mut [f64]) {
        for (d, o) in out.iter_mut().enumerate() {
            *o = self.coordinate(i, d);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first unshifted points of dimension 2 (s = 1, m = 1: v = 1/2, 3/4, 5/8, …) in
    /// natural (not Gray-code) order, x_i = ⊕ v_k over the set bits of i: 1/2, 3/4, 1/4, 5/8.
    #[test]
    fn second_dimension_is_the_textbook_one() {
        let v = directions(1);
        let x = |i: u64| {
            let mut x = 0u32;
            for (k, vk) in v.iter().enumerate() {
                if (i >> k) & 1 == 1 {
                    x ^= vk;
                }
            }
            x as f64 / 2f64.powi(32)
        };
        let got: Vec<f64> = (1..5).map(x).collect();
        assert_eq!(got, vec![0.5, 0.75, 0.25, 0.625]);
    }

    /// Every 2^m points from 0 put exactly one point in each of the 2^m intervals of every
    /// coordinate (a (0, m, 1)-net per coordinate), whatever the shift.
    #[test]
    fn each_coordinate_is_stratified() {
        let p = Points::new(Sampler::Sobol, 7, MAX_DIMENSIONS).unwrap();
        let n = 1u64 << 10;
        for d in 0..MAX_DIMENSIONS {
            let mut hit = vec![0u32; n as usize];
            for i in 0..n {
                hit[(p.coordinate(i, d) * n as f64) as usize] += 1;
            }
            assert!(hit.iter().all(|&h| h == 1), "coordinate {d}");
        }
    }
}
