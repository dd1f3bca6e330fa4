//! The sun of an environment image, taken out of it and turned into a directional light.
//!
//! A sun in an HDRI is a handful of texels tens of thousands of times brighter than the
//! sky. Left in the image, it lights the scene through image-based lighting only: no
//! shadow map sees it, and its specular highlight is smeared by the prefilter. Taken out
//! and given to a [`DirectionalLight`], it casts shadows and lights with the exact BRDF,
//! and the image keeps the sky. Energy is conserved: the light's illuminance is the
//! integral of the removed texels' radiance over their solid angle,
//! `E = Σ L_i · cos θ_i · Δω_i`, with the texel solid angle of an equirectangular image
//! `Δω = (2π / W) · (π / H) · sin θ` (θ the polar angle of the texel's centre).
//!
//! What counts as a sun: the connected texels (8-neighbours, wrapping in longitude)
//! around the brightest one that are brighter than [`SUN_REGION_RATIO`] × the image's
//! median luminance, if the brightest is at least [`SUN_MIN_CONTRAST`] × the median and
//! the region covers at most [`SUN_MAX_SOLID_ANGLE_SR`]. A studio's softboxes fail the
//! last test and stay in the image.

use crate::scene::environment::{Environment, EquirectImage};
use crate::scene::light::{DirectionalLight, LightColor};
use crate::scene::transform::Transform;
use crate::shading::color::luminance;
use crate::shading::ibl::{equirect_direction, rotate_y};
use glam::{Vec2, Vec3};

/// A texel belongs to the sun's region above this multiple of the median luminance.
pub const SUN_REGION_RATIO: f32 = 100.0;

/// The brightest texel must be at least this multiple of the median luminance.
pub const SUN_MIN_CONTRAST: f32 = 1000.0;

/// The largest solid angle a sun's region may cover (sr): 0.01 sr is a disc of about
/// 6.5° across, 150 times the real sun's 6.8e-5 sr, room for the blur and ringing of a
/// small, lossily compressed image.
pub const SUN_MAX_SOLID_ANGLE_SR: f32 = 0.01;

/// A sun found in an environment image by [`split_sun`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageSun {
    /// Unit direction towards the sun, in the image's frame (before the environment's
    /// rotation): the radiance-weighted mean direction of its texels.
    pub direction: Vec3,
    /// Illuminance the removed texels gave a surface facing the sun, per unit of
    /// environment intensity (linear RGB): lux once multiplied by
    /// [`crate::scene::Environment::intensity`].
    pub illuminance: Vec3,
    /// Solid angle of the removed texels (sr).
    pub solid_angle_sr: f32,
    /// How many texels were removed.
    pub texels: usize,
}

impl ImageSun {
    /// The sun's direction in the world once `environment` turns the image (unit).
    pub fn world_direction(&self, environment: &Environment) -> Vec3 {
        rotate_y(self.direction, environment.rotation_y_rad)
    }

    /// A shadow-casting directional light that replaces the sun in `environment` (the
    /// image without it, see [`split_sun`]): its illuminance in lux (× the environment's
    /// intensity), its colour (normalised to luminance 1) and its direction (turned with
    /// the environment).
    pub fn light(&self, environment: &Environment) -> (DirectionalLight, Transform) {
        let direction = self.world_direction(environment);
        let lux = luminance(self.illuminance);
        let color = if lux > 0.0 {
            self.illuminance / lux
        } else {
            Vec3::ONE
        };
        let up = if direction.y.abs() > 0.99 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        (
            DirectionalLight {
                illuminance_lux: lux * environment.intensity,
                color: LightColor::LinearRgb(color),
                cast_shadows: true,
                ..DirectionalLight::default()
            },
            Transform::from_translation(direction).looking_at(Vec3::ZERO, up),
        )
    }
}

/// Solid angle of a texel in row `y` of an equirectangular image of `width` × `height`
/// texels (sr).
pub fn texel_solid_angle_sr(y: u32, width: u32, height: u32) -> f32 {
    let theta = (y as f32 + 0.5) / height as f32 * std::f32::consts::PI;
    (2.0 * std::f32::consts::PI / width as f32)
        * (std::f32::consts::PI / height as f32)
        * theta.sin()
}

/// Finds the sun of `image` (see the module docs); returns it and a copy of the image
/// whose sun texels hold the mean of the texels around them, or `None` when the image
/// has no sun (no texel stands out enough, or the brightest region is too large).
pub fn split_sun(image: &EquirectImage) -> Option<(ImageSun, EquirectImage)> {
    let (w, h) = (image.width as usize, image.height as usize);
    let lum: Vec<f32> = image
        .texels
        .iter()
        .map(|t| luminance(Vec3::from_array(*t)))
        .collect();
    let mut scratch = lum.clone();
    let middle = scratch.len() / 2;
    let median = *scratch.select_nth_unstable_by(middle, f32::total_cmp).1;
    let (brightest, peak) = lum
        .iter()
        .copied()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    if median <= 0.0 || peak < SUN_MIN_CONTRAST * median {
        return None;
    }
    let threshold = SUN_REGION_RATIO * median;
    let neighbours = |i: usize| {
        let (x, y) = ((i % w) as isize, (i / w) as isize);
        (-1isize..=1)
            .flat_map(move |dy| (-1isize..=1).map(move |dx| (dx, dy)))
            .filter(|&d| d != (0, 0))
            .filter_map(move |(dx, dy)| {
                let ny = y + dy;
                (0..h as isize).contains(&ny).then(|| {
                    let nx = (x + dx).rem_euclid(w as isize);
                    ny as usize * w + nx as usize
                })
            })
    };
    let mut in_sun = vec![false; lum.len()];
    let mut region = vec![brightest];
    in_sun[brightest] = true;
    let mut next = 0;
    let mut solid_angle = 0.0f32;
    while next < region.len() {
        let i = region[next];
        next += 1;
        solid_angle += texel_solid_angle_sr((i / w) as u32, image.width, image.height);
        if solid_angle > SUN_MAX_SOLID_ANGLE_SR {
            return None;
        }
        for n in neighbours(i) {
            if !in_sun[n] && lum[n] > threshold {
                in_sun[n] = true;
                region.push(n);
            }
        }
    }
    let direction_of = |i: usize| {
        equirect_direction(Vec2::new(
            ((i % w) as f32 + 0.5) / w as f32,
            ((i / w) as f32 + 0.5) / h as f32,
        ))
    };
    let solid_angle_of = |i: usize| texel_solid_angle_sr((i / w) as u32, image.width, image.height);
    let direction = region
        .iter()
        .map(|&i| direction_of(i) * lum[i] * solid_angle_of(i))
        .sum::<Vec3>()
        .normalize_or(Vec3::Y);
    let illuminance = region
        .iter()
        .map(|&i| {
            Vec3::from_array(image.texels[i])
                * solid_angle_of(i)
                * direction_of(i).dot(direction).max(0.0)
        })
        .sum::<Vec3>();
    let border: Vec<usize> = {
        let mut seen = vec![false; lum.len()];
        region
            .iter()
            .flat_map(|&i| neighbours(i))
            .filter(|&n| !in_sun[n] && !std::mem::replace(&mut seen[n], true))
            .collect()
    };
    let fill = if border.is_empty() {
        Vec3::ZERO
    } else {
        border
            .iter()
            .map(|&i| Vec3::from_array(image.texels[i]))
            .sum::<Vec3>()
            / border.len() as f32
    };
    let mut texels = image.texels.clone();
    for &i in &region {
        texels[i] = fill.to_array();
    }
    let mut sky = EquirectImage::from_texels(image.width, image.height, texels).ok()?;
    sky.path = image.path.clone();
    Some((
        ImageSun {
            direction,
            illuminance,
            solid_angle_sr: solid_angle,
            texels: region.len(),
        },
        sky,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::ibl::equirect_uv;

    /// A 256×128 sky of 1 with a 2×2-texel sun of 5000 towards `towards`.
    fn sky_with_sun(towards: Vec3) -> (EquirectImage, Vec<usize>) {
        let (w, h) = (256usize, 128usize);
        let mut texels = vec![[1.0f32; 3]; w * h];
        let uv = equirect_uv(towards);
        let (cx, cy) = ((uv.x * w as f32) as usize, (uv.y * h as f32) as usize);
        let sun: Vec<usize> = [(0, 0), (1, 0), (0, 1), (1, 1)]
            .iter()
            .map(|(dx, dy)| (cy + dy) * w + (cx + dx) % w)
            .collect();
        for &i in &sun {
            texels[i] = [5000.0, 4000.0, 3000.0];
        }
        (
            EquirectImage::from_texels(w as u32, h as u32, texels).expect("image"),
            sun,
        )
    }

    #[test]
    fn the_sun_becomes_a_light_of_its_integrated_radiance_and_leaves_the_sky() {
        let towards = Vec3::new(0.5, 0.6, -0.4).normalize();
        let (image, sun) = sky_with_sun(towards);
        let (found, sky) = split_sun(&image).expect("a sun");
        assert_eq!(found.texels, 4);
        assert!(
            found.direction.angle_between(towards) < 0.03,
            "{:?}",
            found.direction
        );
        // Σ L Δω cos: the four texels' solid angles, cosines within 1e-3 of 1.
        let (w, h) = (image.width, image.height);
        let expected: f32 = sun
            .iter()
            .map(|&i| 5000.0 * texel_solid_angle_sr((i / w as usize) as u32, w, h))
            .sum();
        assert!(
            (found.illuminance.x - expected).abs() < 2e-3 * expected,
            "{} vs {expected}",
            found.illuminance.x
        );
        assert!((found.illuminance.y / found.illuminance.x - 0.8).abs() < 1e-4);
        for &i in &sun {
            assert_eq!(sky.texels[i], [1.0; 3], "the sky fills the sun's place");
        }
        let mut environment = Environment::image(std::sync::Arc::new(sky), 100.0);
        environment.rotation_y_rad = 1.0;
        let (light, transform) = found.light(&environment);
        let lux = luminance(found.illuminance) * 100.0;
        assert!((light.illuminance_lux - lux).abs() < 1e-3 * lux);
        // The environment's rotation turns the sun with it, as the renderer turns the
        // image (a world direction d looks the image up at rotate_y(d, −rotation)).
        let shines_along = transform.rotation * Vec3::NEG_Z;
        let world = rotate_y(found.direction, 1.0);
        assert!(shines_along.angle_between(-world) < 1e-4);
        assert!(rotate_y(world, -1.0).angle_between(found.direction) < 1e-5);
    }

    #[test]
    fn the_sun_overhead_and_on_the_seam_is_found_whole() {
        for towards in [
            Vec3::new(0.0, 0.99, 0.1).normalize(),
            Vec3::new(0.0, 0.3, 1.0).normalize(),
        ] {
            let (image, _) = sky_with_sun(towards);
            let (found, _) = split_sun(&image).expect("a sun");
            assert_eq!(found.texels, 4, "{towards}");
            let uniform = Environment::uniform(Vec3::ONE);
            let (_, t) = found.light(&uniform);
            assert!(
                t.rotation.is_finite() && t.rotation.is_normalized(),
                "{towards}"
            );
        }
    }

    #[test]
    fn a_uniform_sky_and_a_large_softbox_have_no_sun() {
        let uniform = EquirectImage::from_texels(64, 32, vec![[2.0; 3]; 64 * 32]).expect("image");
        assert!(split_sun(&uniform).is_none());
        let mut texels = vec![[0.01f32; 3]; 64 * 32];
        for y in 8..16 {
            for x in 10..30 {
                texels[y * 64 + x] = [500.0; 3];
            }
        }
        let softbox = EquirectImage::from_texels(64, 32, texels).expect("image");
        assert!(split_sun(&softbox).is_none(), "0.9 sr of softbox is no sun");
        let black = EquirectImage::from_texels(8, 4, vec![[0.0; 3]; 32]).expect("image");
        assert!(split_sun(&black).is_none());
    }
}
