//! Ground truths that the real-time passes are measured against, and the metric they are
//! measured with.

pub mod path;
pub mod thin_lens;

/// Relative mean absolute luminance error of `image` against `reference`:
/// `Σ |L(image) − L(reference)| / Σ L(reference)` over all pixels (Rec. 709 luminance of
/// linear RGB; dimensionless, 0 = identical). `None` if the sizes differ or the reference
/// is black.
pub fn relative_luminance_error(
    image: &image::Rgba32FImage,
    reference: &image::Rgba32FImage,
) -> Option<f64> {
    if image.dimensions() != reference.dimensions() {
        return None;
    }
    let lum = |p: &image::Rgba<f32>| {
        let [r, g, b, _] = p.0;
        f64::from(crate::shading::color::luminance(glam::Vec3::new(r, g, b)))
    };
    let (mut diff, mut total) = (0.0, 0.0);
    for (a, b) in image.pixels().zip(reference.pixels()) {
        diff += (lum(a) - lum(b)).abs();
        total += lum(b).abs();
    }
    (total > 0.0 && diff.is_finite()).then(|| diff / total)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_error() {
        let a = image::Rgba32FImage::from_pixel(4, 4, image::Rgba([1.0, 1.0, 1.0, 1.0]));
        let b = image::Rgba32FImage::from_pixel(4, 4, image::Rgba([1.1, 1.1, 1.1, 1.0]));
        let e = relative_luminance_error(&b, &a).unwrap_or(f64::NAN);
        assert!((e - 0.1).abs() < 1e-6, "{e}");
        assert_eq!(relative_luminance_error(&a, &a), Some(0.0));
        let black = image::Rgba32FImage::new(4, 4);
        assert_eq!(relative_luminance_error(&a, &black), None);
        assert_eq!(
            relative_luminance_error(&a, &image::Rgba32FImage::new(2, 2)),
            None
        );
    }
}
