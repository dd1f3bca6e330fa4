//! CPU twin of `shaders/transparency.wgsl`: weighted blended order-independent
//! transparency (McGuire & Bavoil 2013, "Weighted Blended Order-Independent
//! Transparency", JCGT 2(2)), the `--transparency weighted` mode of the transparent pass.
//!
//! Every blended fragment i, in any order, adds its premultiplied colour `(Lᵢαᵢ, αᵢ)`
//! weighted by `wᵢ = oit_weight(zᵢ, αᵢ)` to an accumulation target, and multiplies a
//! revealage target (cleared to 1) by `1 − αᵢ`. The resolve divides the weighted sum of
//! colours by the weighted sum of coverages and gives the result the coverage
//! `1 − Π(1 − αᵢ)`, which is exact: one layer comes back exactly, and several come back
//! as their weighted average colour over their exact combined coverage.

use glam::{Vec3, Vec4};

/// The weight of a fragment of coverage `alpha` (0..1) at view depth `depth_m` (metres
/// along the view axis): `α · clamp(10 / (10⁻⁵ + (z/5)² + (z/200)⁶), 10⁻², 3·10³)`, one of
/// McGuire & Bavoil's depth weights, which favours near and opaque layers. Dimensionless.
pub fn oit_weight(depth_m: f32, alpha: f32) -> f32 {
    let z = depth_m.abs();
    let falloff = 10.0 / (1e-5 + (z / 5.0).powi(2) + (z / 200.0).powi(6));
    alpha.clamp(0.0, 1.0) * falloff.clamp(1e-2, 3e3)
}

/// The premultiplied colour and coverage `(C·A, A)` of a pixel's blended layers from its
/// accumulation `accum` (Σ wᵢLᵢαᵢ in rgb, Σ wᵢαᵢ in a) and revealage `reveal` (Π(1 − αᵢ)):
/// `C = accum.rgb / accum.a` (the denominator clamped to [10⁻⁴, 5·10⁴]) and `A = 1 −
/// reveal`. The target then composites it with "over", as the sorted mode does.
pub fn oit_resolve(accum: Vec4, reveal: f32) -> Vec4 {
    let coverage = (1.0 - reveal).clamp(0.0, 1.0);
    let color: Vec3 = accum.truncate() / accum.w.clamp(1e-4, 5e4);
    (color * coverage).extend(coverage)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::color::{over, premultiplied};

    #[test]
    fn one_layer_resolves_exactly() {
        let lit = Vec3::new(2.0, 0.5, 0.25);
        for (alpha, z) in [(0.3, 1.0), (0.9, 40.0), (1.0, 0.01), (0.05, 60.0)] {
            let c = premultiplied(lit, alpha);
            let w = oit_weight(z, alpha);
            let got = oit_resolve(c * w, 1.0 - alpha);
            assert!((got - c).abs().max_element() < 1e-5, "{got} vs {c}");
        }
    }

    #[test]
    fn a_faint_far_layer_falls_below_the_denominator_clamp() {
        // α² · falloff below 10⁻⁴: α = 0.05 past about 80 m. The resolve then divides by
        // the clamp, not the sum, and darkens the layer (docs/src/materials.md).
        let c = premultiplied(Vec3::ONE, 0.05);
        let got = oit_resolve(c * oit_weight(500.0, 0.05), 0.95);
        assert!(got.x < 0.5 * c.x, "{got}");
    }

    #[test]
    fn the_coverage_is_exact_and_the_colour_lies_between_the_layers() {
        // Two layers: the combined coverage is "over"'s, whatever the weights; the colour
        // is a weighted mean of the two, closer to the nearer one.
        let (near, far) = (Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 1.0));
        let (a_near, a_far) = (0.5, 0.6);
        let (z_near, z_far) = (2.0, 30.0);
        let layers = [(near, a_near, z_near), (far, a_far, z_far)];
        let mut accum = Vec4::ZERO;
        let mut reveal = 1.0;
        for (lit, a, z) in layers {
            accum += premultiplied(lit, a) * oit_weight(z, a);
            reveal *= 1.0 - a;
        }
        let got = oit_resolve(accum, reveal);
        let exact = over(premultiplied(near, a_near), premultiplied(far, a_far));
        assert!((got.w - exact.w).abs() < 1e-6);
        let colour = got.truncate() / got.w;
        assert!(colour.x > colour.z && colour.x < 1.0, "{colour}");
        // The weights fall with depth and are bounded.
        assert!(oit_weight(1.0, 1.0) > oit_weight(10.0, 1.0));
        assert_eq!(oit_weight(1e6, 1.0), 1e-2);
        assert_eq!(oit_weight(0.0, 1.0), 3e3);
        assert_eq!(oit_weight(5.0, 0.0), 0.0);
    }
}
