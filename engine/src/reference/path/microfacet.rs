//! Shared pieces of the path tracer's lobes and samplers: a shading frame, Smith's
//! masking and the concentric disk map.

use glam::{Mat3, Vec2, Vec3};
use std::f32::consts::PI;

/// An orthonormal basis with `n` as its third column (Duff et al. 2017).
pub fn basis(n: Vec3) -> Mat3 {
    let sign = 1f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    Mat3::from_cols(
        Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vec3::new(b, sign + n.y * n.y * a, -n.y),
        n,
    )
}

/// Smith's masking for anisotropic GGX of widths `alphas` along the first two axes of
/// the local frame, for the local direction `x` (z the normal; either side): the exact
/// separable form, 2|x_z| / (|x_z| + |(α_x x_x, α_y x_y, x_z)|) (Heitz 2014,
/// "Understanding the Masking-Shadowing Function"); with α_x = α_y = α,
/// 2 cos θ / (cos θ + √(α² + (1 − α²) cos² θ)).
pub fn g1_ggx_anisotropic(x: Vec3, alphas: Vec2) -> f32 {
    let z = x.z.abs();
    2.0 * z / (z + Vec3::new(alphas.x * x.x, alphas.y * x.y, x.z).length())
}

/// Concentric map of the unit square onto the unit disk (Shirley & Chiu 1997).
pub fn concentric_disk(xi: Vec2) -> Vec2 {
    let p = xi * 2.0 - Vec2::ONE;
    if p == Vec2::ZERO {
        return Vec2::ZERO;
    }
    let (r, theta) = if p.x.abs() > p.y.abs() {
        (p.x, PI / 4.0 * (p.y / p.x))
    } else {
        (p.y, PI / 2.0 - PI / 4.0 * (p.x / p.y))
    };
    Vec2::new(r * theta.cos(), r * theta.sin())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn anisotropic_masking_is_the_isotropic_one_at_the_projected_width() {
        // Along an azimuth φ the stretched lobe masks as an isotropic one of width
        // √(cos²φ α_x² + sin²φ α_y²); with α_x = α_y it is the isotropic closed form,
        // from either side of the surface.
        let isotropic = |cos: f32, alpha: f32| {
            let a2 = alpha * alpha;
            2.0 * cos / (cos + (a2 + (1.0 - a2) * cos * cos).sqrt())
        };
        for (alphas, phi) in [
            (Vec2::splat(0.3), 0.7f32),
            (Vec2::new(0.7, 0.16), 0.0),
            (Vec2::new(0.7, 0.16), 1.1),
        ] {
            let projected = (phi.cos().powi(2) * alphas.x.powi(2)
                + phi.sin().powi(2) * alphas.y.powi(2))
            .sqrt();
            for theta in [0.1f32, 0.8, 1.4] {
                let x = Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                );
                let expected = isotropic(theta.cos(), projected);
                for side in [x, Vec3::new(x.x, x.y, -x.z)] {
                    let g1 = g1_ggx_anisotropic(side, alphas);
                    assert!(
                        (g1 - expected).abs() < 1e-5,
                        "{alphas} {phi} {theta}: {g1} vs {expected}"
                    );
                }
            }
        }
    }
}
