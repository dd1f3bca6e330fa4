//! Every bind group list (`BindGroupSpec`) against the WGSL of the shader it binds: each
//! listed name is declared at its group and index with the listed kind, and nothing else
//! is bound in those groups. The lists come from the build script's reading of the WGSL
//! declarations (`bindings::declared`); this test derives the same facts independently,
//! from naga's IR of every composed variant (a float texture is `Sampled` where naga's
//! validator finds it sampled or gathered, through function parameters too, else
//! `TextureLoad`), so a mistake in the build script's reading, or a list cut or chosen
//! wrongly, fails here. Each build
//! checked also passes naga's validation.
//!
//! The builds come from the registry: every built-in pass lists its shader builds
//! (`FramePass::shader_builds`), and the shaders that are not a pass's (probe captures,
//! the environment's preprocessing) are listed here. A shader with an entry point that
//! neither names fails the test.

use lumen::reference_gpu;
use lumen::render::bindings::{BindGroupSpec, Binding};
use lumen::render::graph::ShaderBuild;
use lumen::render::indirect::{probe_volume, reflection_probes};
use lumen::render::passes;
use lumen::render::post::tonemap;
use lumen::render::rays::ray_batch;
use lumen::render::rays::scene_rays::{RAYS, RAYS_GROUP};
use lumen::render::shaders::{BUILTIN, ShaderDef, ShaderLibrary};
use lumen::wgpu::naga;
use std::collections::BTreeSet;

/// A binding as the check compares it: a dynamic offset is not in the WGSL, so a
/// `DynamicUniform` compares as a `Uniform`.
fn comparable(kind: Binding) -> Binding {
    match kind {
        Binding::DynamicUniform(_) => Binding::Uniform,
        other => other,
    }
}

/// The global variables some sampling or gathering expression of `module` takes as its
/// texture: directly, in any function (called by this entry point or not: a shared group
/// is declared for every shader that imports it), or through a function's parameter, as
/// naga's validator resolves the (texture, sampler) pairs of each entry point's calls.
fn sampled_globals(module: &naga::Module) -> BTreeSet<naga::Handle<naga::GlobalVariable>> {
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(module)
    .unwrap_or_else(|e| panic!("naga validation: {e:?}"));
    let through_calls = (0..module.entry_points.len())
        .flat_map(|i| info.get_entry_point(i).sampling_set.iter())
        .map(|key| key.image);
    let functions = module
        .functions
        .iter()
        .map(|(_, f)| f)
        .chain(module.entry_points.iter().map(|e| &e.function));
    let direct = functions.flat_map(|function| {
        function.expressions.iter().filter_map(|(_, expression)| {
            let naga::Expression::ImageSample { image, .. } = expression else {
                return None;
            };
            match function.expressions[*image] {
                naga::Expression::GlobalVariable(global) => Some(global),
                _ => None,
            }
        })
    });
    through_calls.chain(direct).collect()
}

/// The kind of binding naga's IR gives global `handle`.
fn kind_of(
    module: &naga::Module,
    handle: naga::Handle<naga::GlobalVariable>,
    sampled: &BTreeSet<naga::Handle<naga::GlobalVariable>>,
) -> Binding {
    let variable = &module.global_variables[handle];
    match (variable.space, &module.types[variable.ty].inner) {
        (naga::AddressSpace::Uniform, _) => Binding::Uniform,
        (naga::AddressSpace::Storage { access }, _) => {
            if access.contains(naga::StorageAccess::STORE) {
                Binding::StorageReadWrite
            } else {
                Binding::Storage
            }
        }
        (_, naga::TypeInner::Sampler { comparison: true }) => Binding::ComparisonSampler,
        (_, naga::TypeInner::Sampler { comparison: false }) => Binding::Sampler,
        (_, naga::TypeInner::Image { dim, class, .. }) => match class {
            naga::ImageClass::Depth { .. } => Binding::Depth,
            naga::ImageClass::Storage {
                format: naga::StorageFormat::Rgba16Float,
                ..
            } => Binding::StorageTexture(lumen::wgpu::TextureFormat::Rgba16Float),
            naga::ImageClass::Sampled { .. } if sampled.contains(&handle) => {
                Binding::Sampled(match dim {
                    naga::ImageDimension::Cube => lumen::wgpu::TextureViewDimension::Cube,
                    _ => lumen::wgpu::TextureViewDimension::D2,
                })
            }
            naga::ImageClass::Sampled { .. } => Binding::TextureLoad,
            other => panic!("{:?}: no Binding for {other:?}", variable.name),
        },
        (space, inner) => panic!("{:?}: no Binding for {space:?} {inner:?}", variable.name),
    }
}

/// (group, binding, name, kind) of every resource `entry` declares in `groups`, sorted.
fn declared(entry: &str, defs: &[ShaderDef], groups: &[u32]) -> Vec<(u32, u32, String, String)> {
    let composed = ShaderLibrary::default()
        .compose(entry, defs)
        .unwrap_or_else(|e| panic!("{entry}: {e}"));
    let module = naga::front::wgsl::parse_str(&composed.source)
        .unwrap_or_else(|e| panic!("{entry}: {}", e.emit_to_string(&composed.source)));
    // The variant validates too (types, uniformity, every switch it turns).
    assert_eq!(composed.first_error(), None, "{entry}");
    let sampled = sampled_globals(&module);
    let mut out: Vec<(u32, u32, String, String)> = module
        .global_variables
        .iter()
        .filter_map(|(handle, v)| {
            let b = v.binding.as_ref()?;
            groups.contains(&b.group).then(|| {
                (
                    b.group,
                    b.binding,
                    v.name.clone().unwrap_or_default(),
                    format!("{:?}", kind_of(&module, handle, &sampled)),
                )
            })
        })
        .collect();
    out.sort();
    out
}

/// (group, binding, name, kind) of the lists, group `i` being `specs[i].0`, sorted.
fn listed(specs: &[(u32, BindGroupSpec)]) -> Vec<(u32, u32, String, String)> {
    let mut out: Vec<(u32, u32, String, String)> = specs
        .iter()
        .flat_map(|(group, spec)| {
            spec.bindings
                .iter()
                .zip(0u32..)
                .map(move |((name, kind), binding)| {
                    let kind = format!("{:?}", comparable(*kind));
                    (*group, binding, name.to_string(), kind)
                })
        })
        .collect();
    out.sort();
    out
}

fn check(entry: &str, defs: &[ShaderDef], specs: &[(u32, BindGroupSpec)]) {
    let groups: Vec<u32> = specs.iter().map(|(g, _)| *g).collect();
    assert_eq!(declared(entry, defs, &groups), listed(specs), "{entry}");
}

/// The shaders that are not a pass's: the probe captures' (bound as listed), the
/// environment's preprocessing (layouts derived from the shader), the full-screen
/// vertex stage every full-screen step imports, and the ray batch and the GPU path
/// tracer.
fn resource_builds() -> Vec<ShaderBuild> {
    vec![
        ShaderBuild::new(
            "probe_capture.wgsl",
            Vec::new(),
            &[(0, probe_volume::CAPTURE)],
        ),
        ShaderBuild::new("probe_bake.wgsl", Vec::new(), &[(0, probe_volume::BAKE)]),
        ShaderBuild::new(
            "reflection_capture.wgsl",
            Vec::new(),
            &[(0, reflection_probes::FACE_COPY)],
        ),
        ShaderBuild::new("ibl_preprocess.wgsl", Vec::new(), &[]),
        ShaderBuild::new(
            "brdf_lut.wgsl",
            lumen::render::indirect::environment_maps::lut_defs(32, 64),
            &[],
        ),
        ShaderBuild::new("fullscreen.wgsl", Vec::new(), &[]),
        ShaderBuild::new(
            "ray_batch.wgsl",
            vec![ShaderDef::U32("RAYS_GROUP", RAYS_GROUP)],
            &[(0, ray_batch::BATCH), (RAYS_GROUP, RAYS)],
        ),
        ShaderBuild::new(
            "path_trace.wgsl",
            vec![ShaderDef::U32("RAYS_GROUP", RAYS_GROUP)],
            &[(0, reference_gpu::BINDINGS), (RAYS_GROUP, RAYS)],
        ),
    ]
}

#[test]
fn every_registered_pass_binds_what_its_shaders_declare() {
    let registry = passes::builtin().expect("the built-in passes");
    let mut covered = BTreeSet::new();
    let mut checked = 0;
    for (pass, builds) in registry.shader_builds() {
        assert!(
            !builds.is_empty(),
            "{}: a built-in pass lists no shader build",
            pass.name()
        );
        for b in builds {
            check(b.shader, &b.defs, &b.groups);
            covered.insert(b.shader);
            checked += 1;
        }
    }
    for b in resource_builds() {
        check(b.shader, &b.defs, &b.groups);
        covered.insert(b.shader);
    }
    assert!(checked > 40, "only {checked} pass builds checked");
    // Every shader with an entry point is some build's.
    let entries: BTreeSet<&str> = BUILTIN
        .iter()
        .filter(|(_, source)| {
            ["@fragment", "@compute", "@vertex"]
                .iter()
                .any(|stage| source.contains(stage))
        })
        .map(|(file, _)| *file)
        .collect();
    let missing: Vec<&&str> = entries.difference(&covered).collect();
    assert!(missing.is_empty(), "shaders no build checks: {missing:?}");
    for shader in ["taa.wgsl", "deform.wgsl"] {
        assert!(covered.contains(shader), "{shader}");
    }
}

#[test]
fn a_wrong_list_does_not_match_its_shader() {
    let output = [
        ShaderDef::U32("TONEMAPPER", 0),
        ShaderDef::Bool("ENCODE_SRGB", true),
    ];
    assert_eq!(
        declared("tonemap.wgsl", &output, &[0]),
        listed(&[(0, tonemap::BINDINGS)])
    );
    // The comparison can fail: a list with one name changed, one binding short, or a
    // texture that is only loaded listed as sampled does not match the shader.
    let renamed = BindGroupSpec {
        bindings: &[("hdr", Binding::TextureLoad), ("postt", Binding::Uniform)],
        ..tonemap::BINDINGS
    };
    let short = BindGroupSpec {
        bindings: &[("hdr", Binding::TextureLoad)],
        ..tonemap::BINDINGS
    };
    let wrong_kind = BindGroupSpec {
        bindings: &[
            (
                "hdr",
                Binding::Sampled(lumen::wgpu::TextureViewDimension::D2),
            ),
            ("post", Binding::Uniform),
        ],
        ..tonemap::BINDINGS
    };
    for wrong in [renamed, short, wrong_kind] {
        assert_ne!(
            declared("tonemap.wgsl", &output, &[0]),
            listed(&[(0, wrong)])
        );
    }
}

#[test]
fn the_ao_trace_binds_the_resolve_steps_bindings_but_its_input() {
    use lumen::render::indirect::gtao::{RESOLVE, TRACE};
    // The input the trace writes is the resolve step's last binding in the WGSL, so the
    // trace's leading part of the list leaves out exactly it.
    let declared = declared(
        "gtao.wgsl",
        &[
            ShaderDef::U32("SLICES", 2),
            ShaderDef::U32("STEPS", 3),
            ShaderDef::Bool("DENOISE", true),
        ],
        &[0],
    );
    let last = declared.last().expect("gtao.wgsl binds group 0");
    assert_eq!((last.1, last.2.as_str()), (4, "raw_ao"));
    assert_eq!(TRACE.bindings.len(), RESOLVE.bindings.len() - 1);
    assert!(TRACE.bindings.iter().all(|(name, _)| *name != "raw_ao"));
}

#[test]
fn a_texture_sampled_only_through_a_parameter_counts_as_sampled() {
    let source = "
        @group(0) @binding(0) var t: texture_2d<f32>;
        @group(0) @binding(1) var s: sampler;
        fn look(x: texture_2d<f32>) -> vec4<f32> {
            return textureSampleLevel(x, s, vec2<f32>(0.5), 0.0);
        }
        @fragment fn fs() -> @location(0) vec4<f32> { return look(t); }
    ";
    let module = naga::front::wgsl::parse_str(source).expect("the WGSL parses");
    let (t, _) = module
        .global_variables
        .iter()
        .find(|(_, v)| v.name.as_deref() == Some("t"))
        .expect("t is declared");
    assert!(sampled_globals(&module).contains(&t));
}
