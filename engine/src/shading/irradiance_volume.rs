//! Diffuse global illumination from a grid of irradiance probes: the formulas, the same as
//! `shaders/irradiance_volume.wgsl` (same names, bound by the parity test).
//!
//! Each probe stores, per direction n of a 6² octahedral map, the irradiance
//! E(n) = Σ L(ω) max(0, n·ω) Δω of the radiance it captured ([`irradiance_weight`]; the
//! cosine-weighted integral over the hemisphere, Lambert 1760) and, per direction of an 8²
//! octahedral map, the first two moments of the distance to the nearest surface
//! (Majercik et al. 2019, "Dynamic Diffuse Global Illumination with Ray-Traced Irradiance
//! Fields", JCGT 8(2)). A shaded point blends the eight probes of its grid cell with
//! trilinear weights times two DDGI terms:
//! - a smooth back-face weight, ((1 + n·d)/2)² + 0.2, for probe direction d;
//! - Chebyshev's bound on the probability that the probe sees the point, from the mean μ
//!   and the mean square of the stored distances (Donnelly & Lauritzen 2006, variance
//!   shadow maps), cubed as DDGI does, so light does not leak through walls.

use glam::{UVec3, Vec2, Vec3};

/// Side of each probe's octahedral map of distance moments, in texels.
pub const OCT_SIDE: u32 = 8;
/// Side of each probe's octahedral map of irradiance in the lighting's atlas, in texels
/// (irradiance varies slowly: DDGI uses 6).
pub const IRRADIANCE_SIDE: u32 = 6;
/// Most probes along one axis of a grid; a volume that would need more gets a wider
/// spacing.
pub const MAX_PROBES_PER_AXIS: u32 = 16;
/// Sharpness of the cosine lobe that spreads one captured distance over the moment texels
/// around its direction (DDGI's depth filter uses 50).
pub const MOMENT_SHARPNESS: f32 = 50.0;
/// Weight of a probe behind the surface, relative to one in front (DDGI's 0.2 floor).
pub const BACKFACE_FLOOR: f32 = 0.2;
/// Fraction of the smallest probe spacing by which a shaded point is pushed along its
/// normal and view direction before visibility is tested (DDGI's self-shadow bias).
pub const SELF_SHADOW_BIAS: f32 = 0.3;

/// Probes along each axis for a box of `extent` metres at `spacing_m` metres: one probe
/// at the centre of each cell, ⌈extent / spacing⌉ cells, at least 1 and at most
/// [`MAX_PROBES_PER_AXIS`]. A zero or non-finite extent or spacing gives one probe on that
/// axis.
pub fn probe_counts(extent: Vec3, spacing_m: f32) -> UVec3 {
    let axis = |e: f32| {
        if !(e.is_finite() && e > 0.0 && spacing_m.is_finite() && spacing_m > 0.0) {
            return 1;
        }
        ((e / spacing_m).ceil().min(MAX_PROBES_PER_AXIS as f32) as u32).max(1)
    };
    UVec3::new(axis(extent.x), axis(extent.y), axis(extent.z))
}

/// The spacing (m per axis) of `counts` probes at the centres of equal cells over a box of
/// `extent` metres; an axis of zero extent gets the largest spacing of the others (1 m
/// when all are zero), so no spacing is zero.
pub fn probe_spacing(extent: Vec3, counts: UVec3) -> Vec3 {
    let axis = |e: f32, c: u32| (e.is_finite() && e > 0.0).then(|| e / c.max(1) as f32);
    let s = [
        axis(extent.x, counts.x),
        axis(extent.y, counts.y),
        axis(extent.z, counts.z),
    ];
    let widest = s.iter().flatten().fold(0.0f32, |a, &b| a.max(b));
    let fill = if widest > 0.0 { widest } else { 1.0 };
    Vec3::new(
        s[0].unwrap_or(fill),
        s[1].unwrap_or(fill),
        s[2].unwrap_or(fill),
    )
}

/// The position of the probe with the smallest coordinates, for `counts` probes at
/// `spacing` centred in the box `min`..`max`.
pub fn probe_origin(min: Vec3, max: Vec3, counts: UVec3, spacing: Vec3) -> Vec3 {
    (min + max) * 0.5 - spacing * (counts.as_vec3() - Vec3::ONE) * 0.5
}

/// DDGI's smooth back-face weight of a probe in direction `to_probe` (unit) from a point
/// with normal `n`: ((1 + n·d)/2)² + [`BACKFACE_FLOOR`].
pub fn backface_weight(to_probe: Vec3, n: Vec3) -> f32 {
    let t = (1.0 + to_probe.dot(n)) * 0.5;
    t * t + BACKFACE_FLOOR
}

/// Chebyshev's upper bound on the probability that a point at `distance` metres from a
/// probe is visible from it, given the mean `mean` (m) and mean square `mean_sq` (m²) of
/// the distances the probe saw in that direction; cubed, as in DDGI, to sharpen the
/// transition. 1 when the point is no farther than the mean.
pub fn chebyshev_visibility(mean: f32, mean_sq: f32, distance: f32) -> f32 {
    // NaN distances count as visible, as in the WGSL twin.
    if distance.partial_cmp(&mean) != Some(std::cmp::Ordering::Greater) {
        return 1.0;
    }
    let variance = (mean_sq - mean * mean).abs().max(1e-6);
    let d = distance - mean;
    let p = variance / (variance + d * d);
    (p * p * p).max(0.0)
}

/// Solid angle (sr) of the texel of a cube face of `size`² texels whose centre lies at
/// face coordinates `xy` in [−1, 1]²: (2/size)² / (1 + x² + y²)^{3/2}.
pub fn cube_texel_solid_angle(xy: Vec2, size: f32) -> f32 {
    let texel = 2.0 / size;
    let r2 = 1.0 + xy.x * xy.x + xy.y * xy.y;
    texel * texel / (r2 * r2.sqrt())
}

/// Weight with which a distance captured in direction `ray` (unit) counts towards the
/// moment texel of direction `texel` (unit): max(0, texel·ray)^[`MOMENT_SHARPNESS`].
pub fn moment_weight(texel: Vec3, ray: Vec3) -> f32 {
    texel.dot(ray).max(0.0).powf(MOMENT_SHARPNESS)
}

/// Weight of radiance captured along `ray` (unit) in the irradiance of a surface with unit
/// normal `normal`: max(0, normal·ray), the cosine of Lambert's law. Summed over a
/// probe's captured pixels times their solid angles ([`cube_texel_solid_angle`]) it gives
/// the irradiance (lx for radiance in cd/m²) of each texel of the probe's irradiance map.
pub fn irradiance_weight(normal: Vec3, ray: Vec3) -> f32 {
    normal.dot(ray).max(0.0)
}

/// The share of a volume's light at `p` (m): 1 inside the box `low`..`high` (m), falling
/// linearly with the distance outside it, measured in probe spacings per axis (`spacing`,
/// m), to 0 one spacing away. Beyond it the environment's irradiance stays: a probe at the
/// grid's edge saw the scene from inside the box, not from a floor metres outside it.
pub fn volume_fade(p: Vec3, low: Vec3, high: Vec3, spacing: Vec3) -> f32 {
    let outside = (low - p).max(p - high).max(Vec3::ZERO) / spacing;
    (1.0 - outside.length()).clamp(0.0, 1.0)
}

/// The normal term of the half-resolution volume's upsample
/// ([`crate::render::indirect::volume_irradiance`]): the weight of a texel looked up at a
/// pixel with normal `texel_n` (unit) for a pixel with normal `n` (unit), max(0, n·n_t)⁸.
/// It is 1 on a flat surface, 0.88 between normals 10° apart and 0 across a right-angled
/// crease, which depth alone does not see (two faces meet at the same depth). The power
/// is Lumen's choice, computed as three squarings.
pub fn upsample_normal_weight(texel_n: Vec3, n: Vec3) -> f32 {
    let c2 = texel_n.dot(n).max(0.0).powi(2);
    let c4 = c2 * c2;
    c4 * c4
}

/// Position, in texels of an atlas of probe tiles, at which a bilinear lookup of direction
/// `d` reads the tile whose first texel is `tile_origin`: each tile is an octahedral map of
/// `side`² texels inside a one-texel border that repeats its edge, so a bilinear read never
/// reaches the next tile.
pub fn atlas_position(tile_origin: Vec2, side: f32, d: Vec3) -> Vec2 {
    tile_origin
        + Vec2::ONE
        + (crate::shading::encoding::oct_encode(d) * 0.5 + Vec2::splat(0.5)) * side
}

/// The direction of the centre of texel `texel` (x, y) of an octahedral map of `side`²
/// texels.
pub fn oct_texel_direction(texel: (u32, u32), side: u32) -> Vec3 {
    let uv = (Vec2::new(texel.0 as f32, texel.1 as f32) + Vec2::splat(0.5)) / side as f32;
    crate::shading::encoding::oct_decode(uv * 2.0 - Vec2::ONE)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::PI;

    #[test]
    fn counts_cover_the_box_and_degenerate_boxes_get_one_probe() {
        let extent = Vec3::new(4.0, 2.0, 0.0);
        let counts = probe_counts(extent, 1.0);
        assert_eq!(counts, UVec3::new(4, 2, 1));
        assert_eq!(probe_counts(Vec3::splat(100.0), 1.0), UVec3::splat(16));
        assert_eq!(probe_counts(Vec3::splat(1.0), 0.0), UVec3::ONE);
        assert_eq!(probe_counts(Vec3::splat(f32::NAN), 1.0), UVec3::ONE);
        let s = probe_spacing(extent, counts);
        assert_eq!(s, Vec3::new(1.0, 1.0, 1.0));
        let o = probe_origin(Vec3::ZERO, extent, counts, s);
        assert_eq!(o, Vec3::new(0.5, 0.5, 0.0));
        assert_eq!(probe_spacing(Vec3::ZERO, UVec3::ONE), Vec3::ONE);
    }

    #[test]
    fn a_cube_s_texels_cover_the_sphere() {
        let size = 16;
        let mut total = 0.0;
        for y in 0..size {
            for x in 0..size {
                let xy = (Vec2::new(x as f32, y as f32) + 0.5) / size as f32 * 2.0 - Vec2::ONE;
                total += cube_texel_solid_angle(xy, size as f32);
            }
        }
        // The centre sample of each texel overestimates its solid angle slightly: 0.1 %
        // in all at 16² per face.
        let sphere = 6.0 * total;
        assert!((sphere / (4.0 * PI) - 1.0).abs() < 2e-3, "{sphere}");
    }

    #[test]
    fn chebyshev_is_one_in_front_and_falls_behind() {
        assert_eq!(chebyshev_visibility(2.0, 4.0, 1.0), 1.0);
        let near = chebyshev_visibility(2.0, 4.01, 2.05);
        let far = chebyshev_visibility(2.0, 4.01, 3.0);
        assert!(near > far && far < 1e-3, "{near} {far}");
        assert!(chebyshev_visibility(0.0, 0.0, f32::NAN) == 1.0);
    }

    #[test]
    fn atlas_lookups_land_on_their_texel_centres() {
        let origin = Vec2::new(16.0, 8.0);
        for side in [IRRADIANCE_SIDE, OCT_SIDE] {
            for y in 0..side {
                for x in 0..side {
                    let d = oct_texel_direction((x, y), side);
                    let c = atlas_position(origin, side as f32, d);
                    let centre = origin + Vec2::new(x as f32 + 1.5, y as f32 + 1.5);
                    assert!((c - centre).length() < 1e-3, "{c} vs {centre}");
                }
            }
        }
        assert!((backface_weight(Vec3::Y, Vec3::Y) - 1.2).abs() < 1e-6);
        assert!((backface_weight(-Vec3::Y, Vec3::Y) - BACKFACE_FLOOR).abs() < 1e-6);
        assert!((moment_weight(Vec3::Y, Vec3::Y) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn the_upsample_s_normal_term_keeps_flat_surfaces_and_drops_creases() {
        assert_eq!(upsample_normal_weight(Vec3::Y, Vec3::Y), 1.0);
        assert_eq!(upsample_normal_weight(Vec3::Y, Vec3::X), 0.0);
        assert_eq!(upsample_normal_weight(Vec3::Y, -Vec3::Y), 0.0);
        let ten_degrees = Vec3::new(10f32.to_radians().sin(), 10f32.to_radians().cos(), 0.0);
        let w = upsample_normal_weight(Vec3::Y, ten_degrees);
        assert!(
            (w - 10f32.to_radians().cos().powi(8)).abs() < 1e-6 && (0.88..0.89).contains(&w),
            "{w}"
        );
    }

    /// The irradiance texels of a capture: summed over the cube's pixels, the cosine
    /// weight times the solid angle is π for every normal (a uniform radiance L gives the
    /// irradiance π L), and a source in one direction lights no normal turned away from
    /// it. Spherical harmonics of bands 0–2, which the probes stored before, give a
    /// normal facing away from such a source about 6 % of the irradiance of one facing it
    /// (0.0625 against 1.0625 of a unit source).
    #[test]
    fn irradiance_texels_integrate_the_cosine_without_ringing() {
        let size = 16;
        let faces = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
        for t in 0..IRRADIANCE_SIDE * IRRADIANCE_SIDE {
            let n =
                oct_texel_direction((t % IRRADIANCE_SIDE, t / IRRADIANCE_SIDE), IRRADIANCE_SIDE);
            let mut total = 0.0;
            for axis in faces {
                let u = if axis.y.abs() > 0.5 { Vec3::X } else { Vec3::Y };
                let v = axis.cross(u);
                for y in 0..size {
                    for x in 0..size {
                        let xy =
                            (Vec2::new(x as f32, y as f32) + 0.5) / size as f32 * 2.0 - Vec2::ONE;
                        let ray = (axis + u * xy.x + v * xy.y).normalize();
                        total +=
                            irradiance_weight(n, ray) * cube_texel_solid_angle(xy, size as f32);
                    }
                }
            }
            assert!((total / PI - 1.0).abs() < 5e-3, "normal {n}: {total}");
            assert_eq!(irradiance_weight(n, -n), 0.0);
        }
        // The harmonics of a unit source along +y: 1.0625 facing it, 0.0625 facing away.
        let sh = crate::shading::ibl::sh_basis(Vec3::Y).map(Vec3::splat);
        let facing = crate::shading::ibl::sh_irradiance(&sh, Vec3::Y).x;
        let away = crate::shading::ibl::sh_irradiance(&sh, -Vec3::Y).x;
        assert!(
            (facing - 1.0625).abs() < 1e-3 && (away - 0.0625).abs() < 1e-3,
            "{facing} {away}"
        );
    }

    #[test]
    fn the_volume_s_light_fades_over_one_spacing_outside_its_box() {
        let (low, high) = (Vec3::ZERO, Vec3::new(4.0, 2.0, 2.0));
        let spacing = Vec3::new(1.0, 0.5, 1.0);
        assert_eq!(
            volume_fade(Vec3::new(2.0, 1.0, 1.0), low, high, spacing),
            1.0
        );
        assert_eq!(volume_fade(high, low, high, spacing), 1.0);
        let half_out = volume_fade(Vec3::new(4.5, 1.0, 1.0), low, high, spacing);
        assert!((half_out - 0.5).abs() < 1e-6, "{half_out}");
        // Half a spacing out along y is a quarter of a metre.
        let above = volume_fade(Vec3::new(2.0, 2.25, 1.0), low, high, spacing);
        assert!((above - 0.5).abs() < 1e-6, "{above}");
        assert_eq!(
            volume_fade(Vec3::new(-1.0, 1.0, 1.0), low, high, spacing),
            0.0
        );
        assert_eq!(
            volume_fade(Vec3::new(20.0, -9.0, 1.0), low, high, spacing),
            0.0
        );
        // Off a corner the distance counts, not the larger axis.
        let corner = volume_fade(Vec3::new(4.5, 2.25, 1.0), low, high, spacing);
        assert!((corner - (1.0 - 0.5f32.sqrt())).abs() < 1e-6, "{corner}");
    }
}
