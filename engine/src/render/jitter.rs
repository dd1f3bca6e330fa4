//! The camera's sub-pixel jitter: where inside its pixel each frame samples the scene.

use bevy_ecs::prelude::Resource;
use glam::{Mat4, Vec2, Vec3};

/// The radical inverse of `index` in `base` (Halton 1964): the digits of `index` mirrored
/// about the radix point, in [0, 1).
pub fn halton(mut index: u32, base: u32) -> f32 {
    let base = base.max(2);
    let (mut result, mut scale) = (0.0f64, 1.0f64);
    while index > 0 {
        scale /= f64::from(base);
        result += scale * f64::from(index % base);
        index /= base;
    }
    result as f32
}

/// This frame's sample position inside each pixel, relative to the pixel's centre, in
/// pixels (x right, y down, each in [−0.5, 0.5)). Zero renders pixel centres.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq)]
pub struct Jitter {
    /// Offset of the sample from the pixel's centre, in pixels.
    pub offset_px: Vec2,
}

impl Jitter {
    /// The `index`th point (from 0) of the Halton (2, 3) sequence, centred on the pixel.
    /// The sequence starts at its second point, so no frame is biased to the pixel's
    /// corner; its points are low-discrepancy, spread evenly over the pixel for any N, so
    /// the average of N renders converges to the box-filtered pixel.
    pub fn halton(index: u32) -> Jitter {
        let i = index.saturating_add(1);
        Jitter {
            offset_px: Vec2::new(halton(i, 2) - 0.5, halton(i, 3) - 0.5),
        }
    }

    /// The clip-space translation that moves the scene so that each pixel's centre
    /// samples the point `offset_px` from it, for an image of `size` pixels: premultiply
    /// a projection by it (the translation scales with w, so it holds for perspective and
    /// orthographic projections alike).
    pub fn clip_matrix(self, size: (u32, u32)) -> Mat4 {
        let (w, h) = (size.0.max(1) as f32, size.1.max(1) as f32);
        let o = if self.offset_px.is_finite() {
            self.offset_px
        } else {
            Vec2::ZERO
        };
        Mat4::from_translation(Vec3::new(-2.0 * o.x / w, 2.0 * o.y / h, 0.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halton_known_values() {
        let base2: Vec<f32> = (1..=4).map(|i| halton(i, 2)).collect();
        assert_eq!(base2, vec![0.5, 0.25, 0.75, 0.125]);
        let base3: Vec<f32> = (1..=4).map(|i| halton(i, 3)).collect();
        let want = [1.0 / 3.0, 2.0 / 3.0, 1.0 / 9.0, 4.0 / 9.0];
        for (g, w) in base3.iter().zip(want) {
            assert!((g - w).abs() < 1e-6, "{g} vs {w}");
        }
    }

    #[test]
    fn jitter_stays_inside_the_pixel_and_averages_to_its_centre() {
        let n = 64;
        let mut sum = Vec2::ZERO;
        for i in 0..n {
            let o = Jitter::halton(i).offset_px;
            assert!(o.abs().max_element() <= 0.5, "{o}");
            sum += o;
        }
        let mean = sum / n as f32;
        assert!(mean.abs().max_element() < 0.02, "mean offset {mean}");
    }

    #[test]
    fn the_matrix_moves_a_pixel_centre_onto_its_sample() {
        let size = (200, 100);
        let j = Jitter {
            offset_px: Vec2::new(0.25, -0.5),
        };
        // A point seen at NDC (0, 0) must land where pixel (100, 50)'s sample was,
        // i.e. the scene moves by −offset: +0.25 px right means the image shifts left.
        let p = j.clip_matrix(size) * glam::Vec4::new(0.0, 0.0, 0.5, 2.0);
        let ndc = Vec2::new(p.x / p.w, p.y / p.w);
        let px = Vec2::new(ndc.x * 0.5 * 200.0, -ndc.y * 0.5 * 100.0);
        assert!((px - Vec2::new(-0.25, 0.5)).length() < 1e-5, "{px}");
        assert_eq!(
            Jitter {
                offset_px: Vec2::NAN
            }
            .clip_matrix(size),
            Mat4::IDENTITY
        );
    }
}
