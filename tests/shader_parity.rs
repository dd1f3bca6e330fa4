//! Every shared shader function (shaders/brdf.wgsl, punctual.wgsl, color.wgsl,
//! encoding.wgsl, ibl.wgsl, camera.wgsl, common.wgsl, skinning.wgsl, …) against its Rust
//! twin (lumen::shading::brdf, punctual, color, encoding, ibl, scene::camera, scene::deform, …) on
//! the same inputs, on the GPU.

use crate::common;
use crate::common::Rng;

use glam::{Mat4, Vec2, Vec3, Vec4};
use lumen::choice::Choice;
use lumen::render::pipelines::create_module;
use lumen::render::shaders::ShaderLibrary;
use lumen::scene::{camera, deform};
use lumen::shading::ambient_occlusion as ao;
use lumen::shading::anisotropy as an;
use lumen::shading::antialiasing as aa;
use lumen::shading::brdf::{self, Surface, VisibilityModel};
use lumen::shading::iridescence as ir;
use lumen::shading::irradiance_volume as gi;
use lumen::shading::reflection_probe as rp;
use lumen::shading::{
    clearcoat, color, encoding, ibl, punctual, shadow_kernel, sheen, transmission, transparency,
};
use wgpu::util::DeviceExt;

const OUTPUTS: usize = 68;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Case {
    n: [f32; 4],
    v: [f32; 4],
    l: [f32; 4],
    base_metallic: [f32; 4],
    params: [f32; 4],
    scalars: [f32; 4],
}

fn cases() -> Vec<Case> {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let edge = [0.0f32, 1.0, -1e-3, 1e-4, 0.5, 1.0 + 1e-6];
    let mut out = Vec::new();
    for i in 0..4096 {
        let n = if i % 7 == 0 { Vec3::Z } else { rng.dir() };
        // Mostly above the horizon, some grazing and below.
        let mut v = rng.dir();
        let mut l = rng.dir();
        if i % 3 != 0 {
            v = if v.dot(n) < 0.0 {
                v - 2.0 * v.dot(n) * n
            } else {
                v
            };
            l = if l.dot(n) < 0.0 {
                l - 2.0 * l.dot(n) * n
            } else {
                l
            };
        }
        let r = if i % 11 == 0 {
            edge[i % edge.len()]
        } else {
            rng.next()
        };
        let x = if i % 5 == 0 {
            edge[(i / 5) % edge.len()]
        } else {
            rng.next()
        };
        let alpha = (rng.next() * rng.next()).max(1e-3);
        let theta = rng.next() * std::f32::consts::FRAC_PI_2;
        out.push(Case {
            n: n.extend(0.0).into(),
            v: v.extend(0.0).into(),
            l: l.extend(0.0).into(),
            base_metallic: [
                rng.next(),
                rng.next(),
                rng.next(),
                if i % 4 == 0 { 1.0 } else { rng.next() },
            ],
            params: [r, rng.next(), (i % 3) as f32, x],
            scalars: [
                alpha,
                theta.cos(),
                theta.sin() * theta.sin(),
                rng.next() * 0.9 + 0.05,
            ],
        });
    }
    out
}

fn model(i: u32) -> VisibilityModel {
    VisibilityModel::ALL[i as usize]
}

/// The Rust side of every output, in the kernel's order; `i` is the case index.
fn expected(i: usize, c: &Case) -> [Vec4; OUTPUTS] {
    let [alpha, n_dot_h, nxh2, k] = c.scalars;
    let [r, spec, m, x] = c.params;
    let base = Vec3::from_slice(&c.base_metallic[..3]);
    let s = Surface {
        base_color: base,
        metallic: c.base_metallic[3],
        perceptual_roughness: r,
        specular_level: spec,
    };
    let n = Vec3::from_slice(&c.n[..3]);
    let v = Vec3::from_slice(&c.v[..3]);
    let l = Vec3::from_slice(&c.l[..3]);
    let e = encoding::oct_encode(n);
    let (sc, off) = (alpha * 10.0, -k);
    let ja = Mat4::from_cols(
        n.extend(0.0),
        v.extend(0.0),
        l.extend(0.0),
        base.extend(1.0),
    );
    let jb = Mat4::from_cols(
        v.extend(0.0),
        l.extend(0.0),
        n.extend(0.0),
        Vec4::new(0.5, -1.0, 2.0, 1.0),
    );
    // An anisotropy direction in n's tangent plane, from l, at the angle whose cosine is
    // n·h.
    let rotation = Vec2::new(n_dot_h, (1.0 - n_dot_h * n_dot_h).max(0.0).sqrt());
    let tangent = an::anisotropy_direction(n, l, x - 0.5, rotation);
    let skin = deform::skin_matrix(
        &[ja, jb, ja * 0.5, jb * -0.25],
        [0, 1, 2, 3],
        [x, n_dot_h, k, r],
    );
    [
        Vec4::new(
            brdf::d_ggx(alpha, n_dot_h, nxh2),
            brdf::g1_schlick_ggx(n_dot_h, k),
            brdf::v_schlick_ggx(n_dot_h, x, k),
            brdf::v_smith_ggx_correlated(n_dot_h, x, alpha),
        ),
        Vec4::new(
            brdf::v_smith_ggx_correlated_fast(n_dot_h, x, alpha),
            brdf::k_direct(r),
            brdf::k_ibl(r),
            brdf::pow5_one_minus(x),
        ),
        brdf::f_schlick(base, x).extend(brdf::fd_lambert()),
        brdf::surface_brdf(n, v, l, &s, model(m as u32)).extend(brdf::visibility(
            model(m as u32),
            n_dot_h,
            x,
            r,
        )),
        brdf::compute_f0(base, c.base_metallic[3], spec).extend(brdf::dielectric_f0(spec)),
        Vec4::new(
            punctual::inverse_square(x * 10.0),
            punctual::range_window(n_dot_h * 10.0, k),
            punctual::distance_attenuation(x * 10.0, k),
            punctual::spot_attenuation(x, sc, off),
        ),
        Vec4::new(
            e.x,
            e.y,
            brdf::clamp_perceptual_roughness(r),
            brdf::perceptual_roughness_to_alpha(r),
        ),
        encoding::oct_decode(e).extend(color::luminance(base)),
        color::tonemap_reinhard(base * 4.0).extend(color::srgb_encode(x)),
        color::tonemap_aces_fitted(base * 4.0).extend(color::srgb_decode(x)),
        color::tonemap_none(base * 2.0 - Vec3::splat(0.5))
            .extend(brdf::g_smith_schlick_ggx(n_dot_h, x, k)),
        brdf::safe_normalize(v * x, Vec3::Y).extend(0.0),
        {
            let packed = encoding::pack_occlusion_receiver(x, c.base_metallic[3]);
            let stored = (packed * 255.0).round() / 255.0;
            Vec4::new(
                packed,
                encoding::unpack_receives_shadows(stored),
                encoding::unpack_occlusion(stored),
                encoding::stored_specular_level(x * 2.5 - 1.0),
            )
        },
        {
            let uv = ibl::equirect_uv(v);
            let rotated = ibl::rotate_y(l, x * 6.0);
            Vec4::new(uv.x, uv.y, rotated.x, rotated.z)
        },
        {
            let sh: [Vec3; 9] = std::array::from_fn(|k| {
                base * (k as f32 * 0.3 + 0.1) - Vec3::splat(0.05 * k as f32)
            });
            ibl::sh_irradiance(&sh, n).extend(ibl::radical_inverse(i as u32))
        },
        {
            let dfg = ibl::dfg_integrate(n_dot_h, r, 32);
            Vec4::new(
                dfg.x,
                dfg.y,
                ibl::energy_compensation(base, dfg).x,
                ibl::specular_occlusion(n_dot_h, x, r),
            )
        },
        ibl::importance_sample_ggx(ibl::hammersley(i as u32 % 64, 64), alpha).extend(0.0),
        color::tonemap_agx(base * 4.0).extend(camera::circle_of_confusion(
            x * 20.0,
            coc_focus(i),
            0.05,
            k * 0.05,
        )),
        color::tonemap_pbr_neutral(base * 4.0).extend(camera::vignetting(x * 3.0, n_dot_h)),
        {
            let projected = ao::gtao_projected_normal(n, v, l);
            let open = ao::gtao_open_horizons(x * 3.0 - 1.5);
            Vec4::new(projected.x, projected.y, open.x, open.y)
        },
        Vec4::new(
            ao::gtao_slice(
                ao::gtao_projected_normal(n, v, l),
                Vec2::new(2.0 * x - 1.0, 2.0 * n_dot_h - 1.0),
            ),
            ao::gtao_slice_visibility(-1.5 * x, 1.5 * n_dot_h, 2.0 * k - 1.0),
            ao::ao_falloff(2.0 * x, n_dot_h + 0.1),
            ao::combine_occlusion(x, n_dot_h),
        ),
        ao::gtao_multi_bounce(x, base).extend(0.0),
        ibl::sample_ggx_vndf(
            Vec3::new(v.x, v.y, v.z.abs() + 1e-3).normalize(),
            alpha,
            ibl::hammersley(i as u32 % 64, 64),
        )
        .extend(0.0),
        Vec4::new(
            gi::backface_weight(v, n),
            gi::chebyshev_visibility(x * 2.0, x * x * 4.0 + k * 0.1, n_dot_h * 4.0),
            gi::cube_texel_solid_angle(Vec2::new(2.0 * x - 1.0, 2.0 * n_dot_h - 1.0), 16.0),
            gi::moment_weight(n, l),
        ),
        gi::oct_texel_direction((i as u32 % 8, (i as u32 / 8) % 8), 6 + i as u32 % 3)
            .extend(ibl::sh_basis(n)[8]),
        {
            let t = gi::atlas_position(Vec2::new((i % 7) as f32 * 8.0, 3.0), 6.0, n);
            let basis = ibl::sh_basis(n);
            Vec4::new(t.x, t.y, basis[1], basis[6])
        },
        rp::parallax_corrected(
            v * 2.0,
            l,
            Vec3::new(-3.0, -2.5, -4.0),
            Vec3::new(3.5, 2.0, 3.0),
            n,
        )
        .extend(rp::box_weight(v * 3.0, n, Vec3::new(2.5, 2.0, 3.0), k)),
        Vec4::new(
            brdf::specular_aa_roughness(r, x * x * 4.0, 1.0, 0.3, 0.2),
            brdf::specular_aa_roughness(r, x * x * 4.0, 0.5 + 0.5 * n_dot_h, 0.159, k),
            brdf::toksvig_variance(0.5 + 0.5 * x),
            brdf::specular_aa_roughness(r, 0.0, 1.0, 0.3, 0.2),
        ),
        aa::running_mean(
            base.extend(x),
            Vec4::new(n.x, n.y, n.z, k) * 3.0,
            if i.is_multiple_of(4) { 1.0 } else { n_dot_h },
        ),
        {
            let c = base * (x * 40.0);
            let k3 = aa::compress_hdr(c);
            k3.extend(aa::perceptual_luma(k3))
        },
        aa::expand_hdr(aa::compress_hdr(base * (x * 40.0))).extend(0.0),
        {
            let y = aa::rgb_to_ycocg(base);
            aa::ycocg_to_rgb(y * Vec3::new(1.0, 0.5, 2.0)).extend(y.y)
        },
        aa::clip_towards_mean(v, base * 0.2, Vec3::new(0.1, 0.2, 0.3) * (k + 0.01)).extend(0.0),
        {
            let column = (x * 8.0).floor();
            let length = column + 1.0 + (n_dot_h * 8.0).floor();
            let reach = Vec2::new(k * 8.0, r * 8.0);
            let coverage = aa::smaa_coverage(column, length, smaa_ends(i), reach);
            let line = aa::line_coverage(x * 3.0, Vec2::new(0.4 * k, v.x), Vec2::new(4.0, v.y));
            Vec4::new(coverage.x, coverage.y, line.x, line.y)
        },
        {
            let ends = smaa_ends(i);
            Vec4::new(aa::smaa_edge(x, n_dot_h, 0.1), ends.x, ends.y, 0.0)
        },
        {
            let lo = base * 0.5;
            let w = aa::cas_weight(lo, base, k);
            aa::cas_apply(base * 0.8, lo * 4.0, w, x.abs() + 0.1).extend(w.y)
        },
        {
            let s = (x.abs() * 3.7).fract();
            let (w, o) = (
                shadow_kernel::shadow_tent_weights(s),
                shadow_kernel::shadow_tent_offsets(s),
            );
            Vec4::new(w.x, w.z, o.x, o.z + o.y)
        },
        color::premultiplied(base * (k * 1e5), x),
        Vec4::new(
            shadow_kernel::blended_shadow_threshold(i as u32, i as u32 / 7),
            shadow_kernel::bayer2(i as u32 & 1, (i as u32 >> 1) & 1) as f32,
            shadow_kernel::shadow_mask_weight(k, 8.0 + x, 8.0 + n_dot_h),
            shadow_kernel::shadow_mask_weight(r, -1.0, 0.5 + x * 20.0),
        ),
        Vec4::new(
            transparency::oit_weight(x * 400.0 - 5.0, k),
            transparency::oit_weight(r * 3.0, 1.0),
            0.0,
            0.0,
        ),
        transparency::oit_resolve((base * 50.0).extend(k * 100.0), x),
        transmission::refracted_direction(n, v, 1.0 + x * 3.0).extend(
            transmission::refraction_path_m(n, v, 1.0 + x * 3.0, r * 0.5),
        ),
        transmission::volume_transmittance(base, x * 3.0, k * 2.0)
            .extend(transmission::transmission_lod(r, 1.0 + x, 256.0)),
        transmission::dispersion_iors(1.0 + x * 3.0, r * 30.0).extend(0.0),
        skin * v.extend(1.0),
        (deform::skin_normal_matrix(glam::Mat3::from_mat4(skin)) * n).extend(0.0),
        Vec4::new(
            clearcoat::clearcoat_albedo(Vec2::new(x, n_dot_h * 0.3), 1.0 + k),
            clearcoat::clearcoat_base_weight(x * 1.5 - 0.25, n_dot_h),
            clearcoat::clearcoat_base_weight(f32::NAN, n_dot_h),
            0.0,
        ),
        Vec4::new(
            sheen::d_charlie(r, n_dot_h),
            sheen::v_neubelt(n_dot_h, x),
            sheen::sheen_base_weight(base, k),
            sheen::clamp_sheen_roughness(r * 1.2 - 0.1),
        ),
        sheen::sheen_brdf(base, r, n_dot_h, x, alpha.sqrt()).extend(0.0),
        {
            let alphas = an::anisotropic_alphas(alpha, x * 1.2 - 0.1);
            Vec4::new(
                alphas.x,
                alphas.y,
                an::d_ggx_anisotropic(alphas, n),
                an::v_smith_ggx_correlated_anisotropic(alphas, v, l),
            )
        },
        {
            let lobe = an::RelitLobe {
                strength: k,
                tint: Vec3::new(base.z, base.y, base.x) * 1.2,
                film: Vec3::new(x, 1.0 + r, 800.0 * n_dot_h),
            };
            let lobes = an::relit_brdf_lobes(n, v, l, tangent, &s, &lobe);
            lobes.specular.extend(lobes.diffuse.x)
        },
        an::anisotropic_bent_normal(n, v, tangent, k * 1.2 - 0.1, r).extend(0.0),
        tangent.extend(0.0),
        brdf::tinted_f0(
            base,
            c.base_metallic[3],
            spec,
            Vec3::new(x * 1.2 - 0.1, k, r),
        )
        .extend(0.0),
        ir::iridescent_fresnel(n_dot_h, 1.0 + 2.0 * r, 500.0 * x, base)
            .extend(ir::interface_f0(1.0 + r, 1.5)),
        ir::film_sensitivity(500.0 * x, base * 3.0).extend(0.0),
        ir::iridescent_mix(base, n_dot_h, Vec3::new(k, 1.0 + r, 500.0 * x)).extend(0.0),
        ir::schlick_f0_of(base, n_dot_h).extend(0.0),
        ir::film_f0(base, n_dot_h, Vec3::new(k, 1.0 + r, 500.0 * x)).extend(0.0),
        {
            let lobe = an::RelitLobe {
                strength: k,
                tint: Vec3::new(base.z, base.y, base.x) * 1.2,
                film: Vec3::new(x, 1.0 + r, 800.0 * n_dot_h),
            };
            let below = l - 2.0 * n.dot(l) * n;
            let color = Vec3::new(base.y, base.z, base.x) * 1.1;
            lumen::shading::diffuse_transmission::diffuse_transmission_lobe(
                n,
                v,
                below,
                &s,
                &lobe,
                x * 1.2 - 0.1,
                color,
            )
            .extend(0.0)
        },
        {
            let lobe = an::RelitLobe {
                strength: k,
                tint: Vec3::new(base.z, base.y, base.x) * 1.2,
                film: Vec3::new(x, 1.0 + r, 800.0 * n_dot_h),
            };
            an::relit_fresnel(&s, &lobe, n_dot_h * 1.2 - 0.1).extend(0.0)
        },
        {
            // The texel's channels reach outside 0..1 and its direction may vanish.
            let texel = base * 1.2 - Vec3::splat(0.1);
            let (strength, d) = an::textured_anisotropy(k, Vec2::new(r, spec), texel);
            Vec4::new(
                strength,
                d.x,
                d.y,
                ir::film_thickness(100.0 * x, 800.0 * n_dot_h, spec * 1.2 - 0.1),
            )
        },
        lumen::scene::texture::normal_from_map(
            n,
            l.extend(x - 0.5),
            Vec3::new(base.z, base.x, base.y),
            k * 3.0 - 1.0,
        )
        .extend(0.0),
        // A neighbour beyond the others, and the background (all depths 0).
        Vec4::new(
            aa::depth_bend(x, k, r, spec, n_dot_h),
            aa::depth_bend(x, 4.0 * k, r, spec, x),
            aa::depth_bend(0.0, 0.0, 0.0, 0.0, 0.0),
            aa::SILHOUETTE_BEND,
        ),
        Vec4::new(
            f32::from(u8::from(aa::creased(n, v))),
            f32::from(u8::from(aa::creased(n, l))),
            n.dot(v),
            aa::CREASE_COSINE,
        ),
        Vec4::new(
            gi::upsample_normal_weight(n, v),
            gi::upsample_normal_weight(n, l),
            gi::upsample_normal_weight(n, n),
            gi::upsample_normal_weight(n, -n),
        ),
        Vec4::new(
            gi::irradiance_weight(n, l),
            gi::irradiance_weight(n, v),
            gi::volume_fade(v * 3.0, FADE_LOW, FADE_HIGH, FADE_SPACING),
            gi::volume_fade(l * 2.0 + n, FADE_LOW, FADE_HIGH, FADE_SPACING),
        ),
        ibl::equirect_direction(Vec2::new(x, n_dot_h)).extend(0.0),
    ]
}

/// The box and spacing of output 66's `volume_fade` (the same in tests/shaders/parity.wgsl):
/// the cases' points lie inside, within a spacing and beyond.
const FADE_LOW: Vec3 = Vec3::new(-1.0, -0.5, -2.0);
const FADE_HIGH: Vec3 = Vec3::new(1.5, 0.5, 1.0);
const FADE_SPACING: Vec3 = Vec3::new(0.5, 0.25, 1.0);

const NAMES: [&str; OUTPUTS] = [
    "d_ggx | g1_schlick_ggx | v_schlick_ggx | v_smith_ggx_correlated",
    "v_smith_ggx_correlated_fast | k_direct | k_ibl | pow5_one_minus",
    "f_schlick | fd_lambert",
    "surface_brdf | visibility",
    "compute_f0 | dielectric_f0",
    "inverse_square | range_window | distance_attenuation | spot_attenuation",
    "oct_encode | clamp_perceptual_roughness | perceptual_roughness_to_alpha",
    "oct_decode | luminance",
    "tonemap_reinhard | srgb_encode",
    "tonemap_aces_fitted | srgb_decode",
    "tonemap_none | g_smith_schlick_ggx",
    "safe_normalize",
    "pack_occlusion_receiver | unpack_receives_shadows | unpack_occlusion | stored_specular_level",
    "equirect_uv | rotate_y",
    "sh_irradiance | radical_inverse",
    "dfg_integrate | energy_compensation | specular_occlusion",
    "importance_sample_ggx | hammersley",
    "tonemap_agx | circle_of_confusion",
    "tonemap_pbr_neutral | vignetting",
    "gtao_projected_normal | gtao_open_horizons",
    "gtao_slice | gtao_slice_visibility | ao_falloff | combine_occlusion",
    "gtao_multi_bounce",
    "sample_ggx_vndf",
    "backface_weight | chebyshev_visibility | cube_texel_solid_angle | moment_weight",
    "oct_texel_direction | sh_basis",
    "atlas_position | sh_basis",
    "parallax_corrected | box_weight",
    "specular_aa_roughness | toksvig_variance",
    "running_mean",
    "compress_hdr | perceptual_luma",
    "expand_hdr",
    "rgb_to_ycocg | ycocg_to_rgb",
    "clip_towards_mean",
    "smaa_coverage | line_coverage",
    "smaa_edge | smaa_end_height",
    "cas_weight | cas_apply",
    "shadow_tent_weights | shadow_tent_offsets",
    "premultiplied",
    "blended_shadow_threshold | bayer2 | shadow_mask_weight",
    "oit_weight",
    "oit_resolve",
    "refracted_direction | refraction_path_m",
    "volume_transmittance | transmission_lod",
    "dispersion_iors",
    "skin_matrix",
    "skin_normal_matrix",
    "clearcoat_albedo | clearcoat_base_weight",
    "d_charlie | v_neubelt | sheen_base_weight | clamp_sheen_roughness",
    "sheen_brdf",
    "anisotropic_alphas | d_ggx_anisotropic | v_smith_ggx_correlated_anisotropic",
    "relit_brdf_lobes",
    "anisotropic_bent_normal",
    "anisotropy_direction",
    "tinted_f0",
    "iridescent_fresnel | interface_f0",
    "film_sensitivity",
    "iridescent_mix",
    "schlick_f0_of",
    "film_f0",
    "diffuse_transmission_lobe",
    "relit_fresnel",
    "textured_anisotropy | film_thickness",
    "normal_from_map",
    "depth_bend | SILHOUETTE_BEND",
    "creased | CREASE_COSINE",
    "upsample_normal_weight",
    "irradiance_weight | volume_fade",
    "equirect_direction",
];

/// The segment ends of case `i` for `smaa_coverage`: every combination of crossing edges
/// and their continuations at both ends, through `smaa_end_height`.
fn smaa_ends(i: usize) -> Vec2 {
    let bit = |b: usize| ((i >> b) & 1) as f32;
    Vec2::new(
        aa::smaa_end_height(Vec2::new(bit(0), bit(1)), Vec2::new(bit(4), bit(5))),
        aa::smaa_end_height(Vec2::new(bit(2), bit(3)), Vec2::new(bit(6), bit(7))),
    )
}

/// Focus distance (m) of case `i` for `circle_of_confusion`: mostly ordinary, some at
/// the focal length (0.05 m), at 0, and at infinity (the largest float).
fn coc_focus(i: usize) -> f32 {
    match i % 9 {
        0 => 0.05,
        1 => 0.0,
        2 => f32::MAX,
        _ => (i % 97) as f32 * 0.25,
    }
}

/// Outputs that are unit vectors (or directions' coordinates).
const UNIT_VECTORS: [usize; 9] = [7, 11, 13, 16, 22, 24, 41, 51, 52];
/// Outputs that are angles from `acos` (or integrals of them), held in absolute terms
/// with a looser tolerance: near ±1, one rounding of the cosine moves `acos` by
/// √(2 · 6e-8) ≈ 3.5e-4 rad.
const ANGLES: [usize; 2] = [19, 20];
/// Outputs of the thin film (and the relit lobes, which include one), held in absolute
/// terms: they take the cosine of phases up to about 85 rad, where one ulp of the argument is 8e-6, and cross 0 (measured: an
/// absolute difference of 5e-7 at a value of 1.25e-4).
const FILM: [usize; 7] = [50, 54, 55, 56, 58, 59, 60];

/// Runs `module`'s `main` (workgroups of 64) over `cases` (binding 0) and returns
/// `outputs` vec4s per case (binding 1); `table`, where given, is binding 2.
fn run_kernel(
    gpu: &lumen::render::device::Gpu,
    module: &wgpu::ShaderModule,
    (cases, table): (&[u8], Option<&[u8]>),
    count: usize,
    outputs: usize,
) -> Vec<[f32; 4]> {
    let input = gpu
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("cases"),
            contents: cases,
            usage: wgpu::BufferUsages::STORAGE,
        });
    let output = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("results"),
        size: (count * outputs * 16) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let pipeline = gpu
        .device
        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("parity"),
            layout: None,
            module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
    let table = table.map(|contents| {
        gpu.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("table"),
                contents,
                usage: wgpu::BufferUsages::STORAGE,
            })
    });
    let mut entries = vec![
        wgpu::BindGroupEntry {
            binding: 0,
            resource: input.as_entire_binding(),
        },
        wgpu::BindGroupEntry {
            binding: 1,
            resource: output.as_entire_binding(),
        },
    ];
    if let Some(table) = &table {
        entries.push(wgpu::BindGroupEntry {
            binding: 2,
            resource: table.as_entire_binding(),
        });
    }
    let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    });
    common::run_compute(
        gpu,
        &pipeline,
        &bind_group,
        count.div_ceil(64) as u32,
        &output,
    )
}

#[test]
fn wgsl_functions_match_their_rust_twins() {
    let gpu = common::gpu();
    let kernel = include_str!("shaders/parity.wgsl");
    let source = ShaderLibrary::default()
        .compose_source("parity.wgsl", kernel, &[])
        .expect("the parity kernel's imports resolve");
    let module = create_module(&gpu, "parity", &source).expect("parity kernel compiles");
    let cases = cases();
    let results = run_kernel(
        &gpu,
        &module,
        (bytemuck::cast_slice(&cases), None),
        cases.len(),
        OUTPUTS,
    );
    assert_eq!(results.len(), cases.len() * OUTPUTS);

    let mut worst = [0.0f32; OUTPUTS];
    for (i, c) in cases.iter().enumerate() {
        let want = expected(i, c);
        for (k, w) in want.iter().enumerate() {
            let got = Vec4::from(results[i * OUTPUTS + k]);
            for ch in 0..4 {
                let (g, e) = (got[ch], w[ch]);
                assert!(
                    g.is_finite() == e.is_finite(),
                    "case {i}, {}: channel {ch}: GPU {g} vs CPU {e}",
                    NAMES[k]
                );
                if !e.is_finite() {
                    continue;
                }
                // Relative error, with an absolute floor for values near 0; unit-vector
                // outputs (GPU sin/cos are not exact near 0) are held in absolute terms.
                let floor = if UNIT_VECTORS.contains(&k) || ANGLES.contains(&k) || FILM.contains(&k)
                {
                    1.0
                } else {
                    1e-3
                };
                let err = (g - e).abs() / e.abs().max(floor);
                worst[k] = worst[k].max(err);
                // dfg_integrate sums 32 samples: one on the horizon may fall on different
                // sides of n·l > 0 on the GPU and the CPU.
                // moment_weight is a 50th power: the GPU's pow (exp2 ∘ log2) multiplies the
                // relative error of its argument by 50.
                let tolerance = if k == 15 {
                    1e-2
                } else if k == 23 || ANGLES.contains(&k) {
                    2e-3
                } else {
                    2e-4
                };
                assert!(
                    err < tolerance,
                    "case {i}, {}: channel {ch}: GPU {g} vs CPU {e} (relative error {err:e})",
                    NAMES[k]
                );
            }
        }
    }
    for (k, w) in worst.iter().enumerate() {
        eprintln!("{:<72} worst relative error {w:.2e}", NAMES[k]);
    }
}

/// A compute kernel over `vec4` cases (binding 0) into `vec4` results (binding 1): the
/// module's `imports`, then `body`, run for case `i` (`c`, the case) in workgroups of 64.
fn vec4_kernel(imports: &str, body: &str) -> String {
    format!(
        "{imports}
@group(0) @binding(0) var<storage, read> cases: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> results: array<vec4<f32>>;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {{
    let i = id.x;
    if i >= arrayLength(&cases) {{
        return;
    }}
    let c = cases[i];
{body}
}}
"
    )
}

/// `metal_rough_verdict` and `brightness_code` of `shaders/validate.wgsl` against
/// `lumen::validate`: every grey code under every metallic class, both floors, and
/// coloured texels.
#[test]
fn the_validator_rules_match_in_wgsl_and_rust() {
    use lumen::validate::{brightness_code, metal_rough_verdict};
    let gpu = common::gpu();
    let kernel = vec4_kernel(
        "#import validate",
        r#"    let base = vec3<f32>(c.x, c.y, c.z);
    let metallic = fract(c.w);
    let strict = c.w >= 1.0;
    results[i] = vec4<f32>(f32(metal_rough_verdict(base, metallic, strict)), f32(brightness_code(base)), 0.0, 0.0);
"#,
    );
    let source = ShaderLibrary::default()
        .compose_source("validate parity", &kernel, &[])
        .expect("the kernel's imports resolve");
    let module = create_module(&gpu, "validate parity", &source).expect("compiles");
    // w: metallic in [0, 1) plus 1 for strict.
    let decode = |c: u32| color::srgb_decode(c as f32 / 255.0);
    let mut cases: Vec<[f32; 4]> = Vec::new();
    for code in 0..=255u32 {
        for metallic in [0u32, 9, 10, 128, 234, 235, 254] {
            for strict in [0.0, 1.0] {
                let g = decode(code);
                cases.push([g, g, g, metallic as f32 / 255.0 + strict]);
            }
        }
    }
    let mut rng = Rng(7);
    for _ in 0..2048 {
        cases.push([
            rng.next(),
            rng.next(),
            rng.next(),
            rng.next() * 0.999 + (rng.next() > 0.5) as u8 as f32,
        ]);
    }
    let results = run_kernel(
        &gpu,
        &module,
        (bytemuck::cast_slice(&cases), None),
        cases.len(),
        1,
    );
    let mut rounding = 0;
    for (i, (c, r)) in cases.iter().zip(&results).enumerate() {
        let base = Vec3::new(c[0], c[1], c[2]);
        let (metallic, strict) = (c[3].fract(), c[3] >= 1.0);
        let code = brightness_code(base);
        let verdict = metal_rough_verdict(base, metallic, strict) as u32;
        let (gpu_verdict, gpu_code) = (r[0] as u32, r[1] as u32);
        if gpu_code != code {
            // A luminance within float error of a half code rounds either way; only
            // random colours may land there.
            assert!(
                i >= 256 * 14 && gpu_code.abs_diff(code) == 1,
                "case {i}: code {gpu_code} vs {code}"
            );
            rounding += 1;
            continue;
        }
        assert_eq!(gpu_verdict, verdict, "case {i}: {c:?}");
    }
    assert!(rounding < 20, "{rounding} half-code roundings");
}

#[test]
fn the_anisotropic_split_sum_table_reads_the_same_in_wgsl_and_rust() {
    // `anisotropic_dfg` (shaders/anisotropic_dfg.wgsl) over the table the layers pass
    // uploads, against `lumen::shading::anisotropy::anisotropic_dfg`, on and between the entries,
    // out of range and NaN; and `view_azimuth` on random views.
    let gpu = common::gpu();
    let kernel = vec4_kernel(
        "#import anisotropy\n#import anisotropic_dfg",
        r#"    let v = vec3<f32>(c.x * 2.0 - 1.0, c.y * 2.0 - 1.0, c.z);
    let azimuth = view_azimuth(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), v);
    results[i] = vec4<f32>(anisotropic_dfg(c.x, c.y, c.z, c.w), azimuth, 0.0);
"#,
    );
    let source = ShaderLibrary::default()
        .compose_source("anisotropic dfg parity", &kernel, &[])
        .expect("the kernel's imports resolve");
    let module = create_module(&gpu, "anisotropic dfg parity", &source).expect("compiles");
    let mut rng = Rng(11);
    let mut cases: Vec<[f32; 4]> = (0..4096)
        .map(|_| {
            let mut c = [0.0f32; 4];
            for x in &mut c {
                *x = rng.next() * 1.2 - 0.1;
            }
            c[1] *= std::f32::consts::FRAC_PI_2;
            c
        })
        .collect();
    cases.extend([
        [1.0, std::f32::consts::FRAC_PI_2, 1.0, 1.0],
        [0.0, 0.0, 0.0, 0.0],
        [f32::NAN, f32::NAN, f32::NAN, f32::NAN],
        [0.5, 10.0, -3.0, 2.0],
    ]);
    let table = an::dfg_table();
    let results = run_kernel(
        &gpu,
        &module,
        (
            bytemuck::cast_slice(&cases),
            Some(bytemuck::cast_slice(table)),
        ),
        cases.len(),
        1,
    );
    let mut worst = 0.0f32;
    for (c, r) in cases.iter().zip(&results) {
        let want = an::anisotropic_dfg(table, c[0], c[1], c[2], c[3]);
        let got = Vec2::new(r[0], r[1]);
        let err = (got - want).abs().max_element();
        worst = worst.max(err);
        assert!(err < 1e-5, "{c:?}: GPU {got} vs CPU {want}");
        let v = Vec3::new(c[0] * 2.0 - 1.0, c[1] * 2.0 - 1.0, c[2]);
        if c.iter().all(|x| x.is_finite()) {
            let azimuth = an::view_azimuth(Vec3::X, Vec3::Y, v);
            assert!(
                (r[2] - azimuth).abs() < 1e-5,
                "{c:?}: GPU {} vs CPU {azimuth}",
                r[2]
            );
        }
    }
    eprintln!("anisotropic_dfg worst absolute difference {worst:.2e}");
}
