//! Observation noise and delay per segment (`envspec::noise`): noise drawn from the env's stream
//! in observation order (segment by segment, element by element, only segments that declare
//! noise), added before the segment's clip; then each delayed segment swapped with its ring
//! buffer, so it reports the value of `delay` steps ago. Buffers are sized when the env is built:
//! stepping allocates nothing.

use envspec::Field;
use envspec::ResolvedSpec;
use envspec::noise::{Noise, NoiseKind};

use crate::rng::NumpyRng;

/// The past values of one delayed segment: `delay` slots of the segment's length.
struct Ring {
    offset: usize,
    len: usize,
    delay: usize,
    /// The slot holding the oldest value (the one reported next).
    head: usize,
    buf: Vec<f64>,
}

pub(crate) struct ObsNoise {
    /// Per resolved segment (by index): its noise, if any.
    noise: Vec<Option<Noise>>,
    any_noise: bool,
    rings: Vec<Ring>,
}

/// One noise value: Playground's `(2u − 1)·level·scale` or `z·level·scale`, left to right, or
/// `(level·scale)·draw` with `order = "level_scale_draw"`.
#[inline]
fn draw(n: &Noise, rng: &mut NumpyRng) -> f64 {
    let x = match n.kind {
        NoiseKind::Uniform => 2.0 * rng.next_f64() - 1.0,
        NoiseKind::Gaussian => rng.standard_normal(),
    };
    if n.scale_first {
        (n.level * n.scale) * x
    } else {
        x * n.level * n.scale
    }
}

impl ObsNoise {
    /// The delay rings' size in bytes (part of an env's memory, for the vector-env check).
    pub(crate) fn bytes(&self) -> u64 {
        self.rings
            .iter()
            .map(|r| (r.buf.len() * std::mem::size_of::<f64>()) as u64)
            .sum()
    }
    /// None when the spec declares no observation noise or delay (the plain kernel runs).
    pub(crate) fn new(spec: &ResolvedSpec) -> Option<ObsNoise> {
        let c = &spec.corruption;
        if c.segments.is_empty() {
            return None;
        }
        let mut noise = vec![None; spec.observation.len()];
        let mut rings = vec![];
        for s in &c.segments {
            let seg = &spec.observation[s.segment];
            noise[s.segment] = s.noise;
            if s.delay > 0 {
                rings.push(Ring {
                    offset: seg.offset,
                    len: seg.len(),
                    delay: s.delay,
                    head: 0,
                    buf: vec![0.0; s.delay * seg.len()],
                });
            }
        }
        Some(ObsNoise {
            any_noise: noise.iter().any(Option::is_some),
            noise,
            rings,
        })
    }

    /// Write the observation into `out`: segments with noise added before clipping, then delays.
    /// At reset every delay slot is filled with the reset observation.
    pub(crate) fn write<'a>(
        &mut self,
        spec: &ResolvedSpec,
        field: impl Fn(Field) -> &'a [f64],
        out: &mut [f64],
        rng: &mut NumpyRng,
        reset: bool,
    ) {
        if self.any_noise {
            let noise = &self.noise;
            crate::observe::write_segments_with(&spec.observation, field, out, |i, x| match &noise
                [i]
            {
                Some(n) => x + draw(n, rng),
                None => x,
            });
        } else {
            crate::observe::write_segments(&spec.observation, field, out);
        }
        for r in &mut self.rings {
            let now = &mut out[r.offset..r.offset + r.len];
            if reset {
                for slot in r.buf.chunks_exact_mut(r.len) {
                    slot.copy_from_slice(now);
                }
                r.head = 0;
            } else {
                // The oldest slot (`delay` steps ago) goes out; the current value takes its place.
                let slot = &mut r.buf[r.head * r.len..(r.head + 1) * r.len];
                now.swap_with_slice(slot);
                r.head = (r.head + 1) % r.delay;
            }
        }
    }
}
