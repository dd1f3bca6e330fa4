//! G-buffer encodings on the CPU, the same as `shaders/encoding.wgsl`.
//!
//! Normals are stored octahedrally (Cigolle et al. 2014, "A Survey of Efficient
//! Representations for Independent Unit Vectors", JCGT 3(2)): a unit vector maps to a
//! point of the square [−1, 1]², which the G-buffer keeps in two 16-bit floats.

use glam::{Vec2, Vec3};

/// `±1` with the sign of `v`, and +1 for zero (so that the octahedral fold is defined).
fn sign_not_zero(v: Vec2) -> Vec2 {
    Vec2::new(
        if v.x >= 0.0 { 1.0 } else { -1.0 },
        if v.y >= 0.0 { 1.0 } else { -1.0 },
    )
}

/// Octahedral encoding of a unit vector into [−1, 1]². A zero or non-finite vector
/// encodes as +Z.
pub fn oct_encode(n: Vec3) -> Vec2 {
    let l1 = n.x.abs() + n.y.abs() + n.z.abs();
    if !(l1 > 1e-20 && l1.is_finite()) {
        return Vec2::ZERO;
    }
    let p = Vec2::new(n.x, n.y) / l1;
    if n.z <= 0.0 {
        (Vec2::ONE - Vec2::new(p.y, p.x).abs()) * sign_not_zero(p)
    } else {
        p
    }
}

/// Decodes [`oct_encode`]; always returns a unit vector.
pub fn oct_decode(e: Vec2) -> Vec3 {
    let mut v = Vec3::new(e.x, e.y, 1.0 - e.x.abs() - e.y.abs());
    if v.z < 0.0 {
        let folded = (Vec2::ONE - Vec2::new(v.y, v.x).abs()) * sign_not_zero(Vec2::new(v.x, v.y));
        v.x = folded.x;
        v.y = folded.y;
    }
    v.normalize()
}

/// Packs ambient occlusion (7 bits) and the "receives shadows" flag (the top bit) into one
/// 8-bit UNORM channel (`gbuffer0.a`). NaN occlusion counts as 1 (open).
pub fn pack_occlusion_receiver(occlusion: f32, receives_shadows: f32) -> f32 {
    let ao = if occlusion.is_nan() {
        1.0
    } else {
        occlusion.clamp(0.0, 1.0)
    };
    ((ao * 127.0).round() + if receives_shadows > 0.5 { 128.0 } else { 0.0 }) / 255.0
}

/// The specular level an unlit surface (`KHR_materials_unlit`) stores in `gbuffer2.a`
/// and carries in its instance's `params.z`: any negative level marks one.
pub const UNLIT_SPECULAR_LEVEL: f32 = -1.0;

/// The specular level stored in `gbuffer2.a`: `level` clamped to 0..1, or
/// [`UNLIT_SPECULAR_LEVEL`] where it is negative (an unlit surface).
pub fn stored_specular_level(level: f32) -> f32 {
    if level < 0.0 {
        UNLIT_SPECULAR_LEVEL
    } else {
        level.clamp(0.0, 1.0)
    }
}

/// Whether a stored specular level marks an unlit surface.
pub fn is_unlit(stored_level: f32) -> bool {
    stored_level < 0.0
}

/// The flag of [`pack_occlusion_receiver`]: 1 or 0.
pub fn unpack_receives_shadows(a: f32) -> f32 {
    if (a * 255.0).round() >= 128.0 {
        1.0
    } else {
        0.0
    }
}

/// The occlusion of [`pack_occlusion_receiver`], 0..1 in steps of 1/127.
pub fn unpack_occlusion(a: f32) -> f32 {
    let v = (a * 255.0).round();
    (v - if v >= 128.0 { 128.0 } else { 0.0 }) / 127.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use half::f16;

    fn quantise_f16(e: Vec2) -> Vec2 {
        Vec2::new(f16::from_f32(e.x).to_f32(), f16::from_f32(e.y).to_f32())
    }

    #[test]
    fn round_trip_through_f16_is_within_a_tenth_of_a_degree() {
        // Fibonacci sphere: 100k directions, plus the axes and the octahedron's seams.
        let mut dirs: Vec<Vec3> = vec![
            Vec3::X,
            -Vec3::X,
            Vec3::Y,
            -Vec3::Y,
            Vec3::Z,
            -Vec3::Z,
            Vec3::new(1.0, 1.0, 0.0).normalize(),
            Vec3::new(-1.0, 1.0, -1e-7).normalize(),
        ];
        let count = 100_000;
        let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
        for i in 0..count {
            let y = 1.0 - 2.0 * (i as f32 + 0.5) / count as f32;
            let r = (1.0 - y * y).sqrt();
            let phi = golden * i as f32;
            dirs.push(Vec3::new(r * phi.cos(), y, r * phi.sin()));
        }
        let mut worst = 0.0f32;
        for n in dirs {
            let e = oct_encode(n);
            assert!(e.x.abs() <= 1.0 && e.y.abs() <= 1.0);
            let exact = oct_decode(e);
            assert!(exact.angle_between(n) < 1e-3, "{n} → {e} → {exact}");
            let d = oct_decode(quantise_f16(e));
            worst = worst.max(d.dot(n).clamp(-1.0, 1.0).acos().to_degrees());
        }
        assert!(worst < 0.1, "worst f16 round-trip error {worst}°");
    }

    #[test]
    fn occlusion_and_receiver_flag_share_a_byte() {
        for receives in [0.0f32, 1.0] {
            for i in 0..=127 {
                let ao = i as f32 / 127.0;
                // Through an 8-bit UNORM store and load.
                let stored = (pack_occlusion_receiver(ao, receives) * 255.0).round() / 255.0;
                assert_eq!(unpack_receives_shadows(stored), receives);
                assert!((unpack_occlusion(stored) - ao).abs() < 1e-6, "{ao}");
            }
        }
        assert_eq!(
            unpack_occlusion(pack_occlusion_receiver(f32::NAN, 1.0)),
            1.0
        );
        assert_eq!(unpack_occlusion(pack_occlusion_receiver(-3.0, 0.0)), 0.0);
    }

    #[test]
    fn degenerate_input_decodes_to_a_unit_vector() {
        for n in [
            Vec3::ZERO,
            Vec3::splat(f32::NAN),
            Vec3::splat(f32::INFINITY),
        ] {
            let d = oct_decode(oct_encode(n));
            assert!((d.length() - 1.0).abs() < 1e-6);
        }
    }
}
