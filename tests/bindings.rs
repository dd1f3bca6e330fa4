//! Every bind group list (`BindGroupSpec`) against the WGSL of the shader it binds: each
//! listed name is declared at its group and index, and nothing else is bound in those
//! groups. The list is the one source both the layout and the group are built from, so
//! this is what keeps Rust and WGSL in step. Each variant checked also passes naga's
//! validation.

use lumen::brdf::VisibilityModel;
use lumen::quality::ShadowFilter;
use lumen::render::antialiasing::{accumulate, copy, fxaa, prepare, resolve, smaa};
use lumen::render::bindings::{BindGroupSpec, Binding};
use lumen::render::indirect::ambient_occlusion::{self, AoPass, AoVariant};
use lumen::render::indirect::depth_pyramid;
use lumen::render::indirect::irradiance_volume;
use lumen::render::indirect::reflection_probes;
use lumen::render::indirect::reflections::{self, SsrPass, SsrVariant};
use lumen::render::indirect::volume_irradiance;
use lumen::render::layers::{self, Layer, LayersPass};
use lumen::render::lighting::{LightingPass, LightingVariant};
use lumen::render::shaders::{ShaderDef, ShaderLibrary};
use lumen::render::tonemap;
use lumen::render::transparent::{self, TransparentPass, TransparentVariant};
use lumen::render::{debug_view, gbuffer, light_culling, lighting, material_maps, shadow, sky};
use lumen::wgpu::naga;

/// (group, binding, name) of every resource `entry` declares in `groups`, sorted.
fn declared(entry: &str, defs: &[ShaderDef], groups: &[u32]) -> Vec<(u32, u32, String)> {
    let composed = ShaderLibrary::default()
        .compose(entry, defs)
        .unwrap_or_else(|e| panic!("{entry}: {e}"));
    let module = naga::front::wgsl::parse_str(&composed.source)
        .unwrap_or_else(|e| panic!("{entry}: {}", e.emit_to_string(&composed.source)));
    // The variant validates too (types, uniformity, every switch it turns).
    assert_eq!(composed.first_error(), None, "{entry}");
    let mut out: Vec<(u32, u32, String)> = module
        .global_variables
        .iter()
        .filter_map(|(_, v)| {
            let b = v.binding.as_ref()?;
            groups
                .contains(&b.group)
                .then(|| (b.group, b.binding, v.name.clone().unwrap_or_default()))
        })
        .collect();
    out.sort();
    out
}

/// (group, binding, name) of the lists, group `i` being `specs[i].0`, sorted.
fn listed(specs: &[(u32, BindGroupSpec)]) -> Vec<(u32, u32, String)> {
    let mut out: Vec<(u32, u32, String)> = specs
        .iter()
        .flat_map(|(group, spec)| {
            spec.bindings
                .iter()
                .zip(0u32..)
                .map(move |((name, _), binding)| (*group, binding, name.to_string()))
        })
        .collect();
    out.sort();
    out
}

fn check(entry: &str, defs: &[ShaderDef], specs: &[(u32, BindGroupSpec)]) {
    let groups: Vec<u32> = specs.iter().map(|(g, _)| *g).collect();
    assert_eq!(declared(entry, defs, &groups), listed(specs), "{entry}");
}

#[test]
fn every_bind_group_list_matches_its_shader() {
    let everything = LightingVariant {
        directional: true,
        point: true,
        spot: true,
        visibility: VisibilityModel::default(),
        shadows: [true; 3],
        shadowed_counts: [2, 1, 1],
        shadow_filter: ShadowFilter::Pcss,
        environment: true,
        env_map: true,
        energy_compensation: true,
        screen_ao: true,
        ao_multi_bounce: true,
        irradiance_volume: true,
        reflection_probes: 2,
        light_culling: true,
        uniform_lights: true,
        uniform_shadow_views: true,
        shadow_mask: 2,
        shadow_mask_lights: 3,
        half_volume: true,
    };
    check(
        "lighting.wgsl",
        &LightingPass::defs(everything, 8),
        &[
            (0, lighting::VIEW_AND_GBUFFER),
            (1, lighting::LIGHTS_AND_SHADOWS),
            (2, lighting::ENVIRONMENT),
            (3, lighting::PROBES),
        ],
    );
    // The passes that read the extension textures, with the maps' units and without
    // (extension_units_unbound.wgsl in their place).
    for (units, maps) in [
        (true, material_maps::BINDINGS),
        (false, material_maps::CORE_BINDINGS),
    ] {
        // Every variant of the blended lobes: the layered ones turn switches, the others
        // read constants.
        for lobes in transparent::BlendedLobes::all() {
            check(
                "transparent.wgsl",
                &TransparentPass::defs(
                    (
                        TransparentVariant::of(
                            everything,
                            lumen::quality::Transparency::WeightedBlended,
                            true,
                        ),
                        lobes,
                    ),
                    8,
                    units,
                ),
                &[
                    (0, transparent::VIEW),
                    (1, lighting::LIGHTS_AND_SHADOWS),
                    (2, lighting::ENVIRONMENT),
                    (3, lighting::PROBES),
                    (4, maps),
                ],
            );
        }
        check(
            "layers.wgsl",
            &LayersPass::defs(everything, Layer::Sheen, 8, units),
            &[
                (0, layers::VIEW),
                (1, lighting::LIGHTS_AND_SHADOWS),
                (2, lighting::ENVIRONMENT),
                (3, lighting::PROBES),
                (4, maps),
            ],
        );
    }
    check(
        "shadow_mask.wgsl",
        &shadow::mask::ShadowMaskPass::defs(
            shadow::mask::MaskVariant {
                scale: 2,
                lights: 3,
                filter: ShadowFilter::Pcss,
                uniform_lights: true,
                uniform_shadow_views: true,
            },
            8,
        ),
        &[
            (0, shadow::mask::VIEW_AND_GBUFFER),
            (1, lighting::LIGHTS_AND_SHADOWS),
        ],
    );
    check(
        "volume_irradiance.wgsl",
        &[],
        &[(0, volume_irradiance::VIEW_AND_GBUFFER)],
    );
    // Its groups 1 and 2 are empty, and of the probes' group 3 it declares the volume's
    // four bindings.
    assert_eq!(declared("volume_irradiance.wgsl", &[], &[1, 2]), Vec::new());
    assert_eq!(
        declared("volume_irradiance.wgsl", &[], &[3]),
        listed(&[(3, lighting::PROBES)])[..4].to_vec()
    );
    check(
        "transparent_resolve.wgsl",
        &[],
        &[(0, transparent::weighted::RESOLVE_BINDINGS)],
    );
    check(
        "probe_capture.wgsl",
        &[],
        &[(0, irradiance_volume::CAPTURE)],
    );
    check("probe_bake.wgsl", &[], &[(0, irradiance_volume::BAKE)]);
    check(
        "reflection_capture.wgsl",
        &[],
        &[(0, reflection_probes::FACE_COPY)],
    );
    check(
        "gbuffer.wgsl",
        &[
            ShaderDef::Bool("SPECULAR_AA", true),
            material_maps::group_def(1),
        ],
        &[
            (0, gbuffer::VIEW),
            (1, material_maps::CORE_BINDINGS),
            (2, gbuffer::MOTION_BINDINGS),
        ],
    );
    check("accumulate.wgsl", &[], &[(0, accumulate::BINDINGS)]);
    check(
        "frame_mips.wgsl",
        &[],
        &[(0, transparent::transmission_source::BINDINGS)],
    );
    check("copy.wgsl", &[], &[(0, copy::BINDINGS)]);
    check("aa_prepare.wgsl", &[], &[(0, prepare::BINDINGS)]);
    check("taa_resolve.wgsl", &[], &[(0, resolve::BINDINGS)]);
    check("smaa_edges.wgsl", &[], &[(0, smaa::EDGES_BINDINGS)]);
    check(
        "smaa_weights.wgsl",
        smaa::WEIGHTS_DEFS,
        &[(0, smaa::WEIGHTS_BINDINGS)],
    );
    check("smaa_blend.wgsl", &[], &[(0, smaa::BLEND_BINDINGS)]);
    check("fxaa.wgsl", &[], &[(0, fxaa::BINDINGS)]);
    check(
        "shadow.wgsl",
        &[material_maps::group_def(1)],
        &[
            (0, shadow::pass::CASTERS),
            (1, material_maps::CORE_BINDINGS),
        ],
    );
    check(
        "sky.wgsl",
        &[ShaderDef::Bool("ENV_MAP", true)],
        &[(0, sky::BINDINGS)],
    );
    check(
        "light_culling.wgsl",
        &[
            ShaderDef::Bool("UNIFORM_LIGHTS", true),
            ShaderDef::U32("UNIFORM_LIGHT_CAPACITY", 8),
        ],
        &[(0, light_culling::BINDINGS)],
    );
    let output = [
        ShaderDef::U32("TONEMAPPER", 0),
        ShaderDef::Bool("ENCODE_SRGB", true),
    ];
    check("tonemap.wgsl", &output, &[(0, tonemap::BINDINGS)]);
    check(
        "debug_view.wgsl",
        &[
            ShaderDef::U32("DEBUG_VIEW", 1),
            ShaderDef::Bool("ENCODE_SRGB", true),
            ShaderDef::Bool("SCREEN_AO", true),
        ],
        &[(0, debug_view::BINDINGS)],
    );
    check(
        "gtao.wgsl",
        &AoPass::defs(AoVariant {
            slices: 2,
            steps: 3,
            denoise: true,
        }),
        &[(0, ambient_occlusion::RESOLVE)],
    );
    check("depth_pyramid.wgsl", &[], &[(0, depth_pyramid::BINDINGS)]);
    check(
        "ssr.wgsl",
        &SsrPass::defs(SsrVariant {
            rays: 2,
            steps: 16,
            environment: true,
            env_map: true,
            energy_compensation: true,
            screen_ao: true,
            reflection_probes: 2,
            format: wgpu::TextureFormat::Rgba16Float,
            half: true,
        }),
        &[
            (0, reflections::SSR),
            (1, lighting::ENVIRONMENT),
            (2, reflections::SSR_HALF),
            (3, lighting::PROBES),
        ],
    );
    assert_eq!(
        ambient_occlusion::TRACE.bindings,
        &ambient_occlusion::RESOLVE.bindings[..4],
        "the trace step binds the resolve step's bindings but its input"
    );
    // The comparison can fail: a list with one name changed, or one binding short, does
    // not match the shader.
    let renamed = BindGroupSpec {
        bindings: &[("hdr", Binding::TextureLoad), ("postt", Binding::Uniform)],
        ..tonemap::BINDINGS
    };
    let short = BindGroupSpec {
        bindings: &[("hdr", Binding::TextureLoad)],
        ..tonemap::BINDINGS
    };
    for wrong in [renamed, short] {
        assert_ne!(
            declared("tonemap.wgsl", &output, &[0]),
            listed(&[(0, wrong)])
        );
    }
}
