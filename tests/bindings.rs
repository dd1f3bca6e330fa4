//! Every bind group list (`BindGroupSpec`) against the WGSL of the shader it binds: each
//! listed name is declared at its group and index, and nothing else is bound in those
//! groups. The list is the one source both the layout and the group are built from, so
//! this is what keeps Rust and WGSL in step. Each build checked also passes naga's
//! validation.
//!
//! The builds come from the registry: every built-in pass lists its shader builds
//! (`FramePass::shader_builds`), and the shaders that are not a pass's (probe captures,
//! the environment's preprocessing) are listed here. A shader with an entry point that
//! neither names fails the test.

use lumen::render::bindings::{BindGroupSpec, Binding};
use lumen::render::graph::ShaderBuild;
use lumen::render::indirect::{probe_volume, reflection_probes};
use lumen::render::passes;
use lumen::render::post::tonemap;
use lumen::render::shaders::{BUILTIN, ShaderDef, ShaderLibrary};
use lumen::wgpu::naga;
use std::collections::BTreeSet;

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

/// The shaders that are not a pass's: the probe captures' (bound as listed), the
/// environment's preprocessing (layouts derived from the shader), and the full-screen
/// vertex stage every full-screen step imports.
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

#[test]
fn the_ao_trace_binds_the_resolve_steps_bindings_but_its_input() {
    use lumen::render::indirect::gtao::{RESOLVE, TRACE};
    assert_eq!(TRACE.bindings, &RESOLVE.bindings[..4]);
}
