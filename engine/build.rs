//! Lists every WGSL module in `shaders/` for `render::shaders::BUILTIN`, so that a new
//! shader file is compiled into the binary without being registered anywhere, and writes
//! the bindings each shader declares (`render::bindings::declared`), so that no Rust list
//! restates a WGSL declaration.

use std::fmt::Write as _;
use std::path::PathBuf;

fn main() {
    let manifest = std::env::var("CARGO_MANIFEST_DIR").unwrap_or_else(|_| ".".into());
    let dir = PathBuf::from(manifest).join("..").join("shaders");
    println!("cargo:rerun-if-changed={}", dir.display());
    let mut files: Vec<PathBuf> = match std::fs::read_dir(&dir) {
        Ok(entries) => entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "wgsl"))
            .collect(),
        Err(e) => panic!("cannot read {}: {e}", dir.display()),
    };
    files.sort();
    let mut out = String::from("&[\n");
    for path in &files {
        let name = path
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or_else(|| panic!("{} has no UTF-8 name", path.display()));
        let absolute = path
            .canonicalize()
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let _ = writeln!(
            out,
            "    ({name:?}, include_str!({:?})),",
            absolute.display().to_string()
        );
    }
    out.push(']');
    let target = PathBuf::from(std::env::var("OUT_DIR").unwrap_or_else(|_| ".".into()))
        .join("builtin_shaders.rs");
    if let Err(e) = std::fs::write(&target, out) {
        panic!("cannot write {}: {e}", target.display());
    }
    let sources: Vec<(String, String)> = files
        .iter()
        .map(|path| {
            let stem = path
                .file_stem()
                .and_then(|n| n.to_str())
                .unwrap_or_else(|| panic!("{} has no UTF-8 name", path.display()));
            let text = std::fs::read_to_string(path)
                .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
            (stem.to_string(), text)
        })
        .collect();
    let target = PathBuf::from(std::env::var("OUT_DIR").unwrap_or_else(|_| ".".into()))
        .join("declared_bindings.rs");
    if let Err(e) = std::fs::write(&target, declared_bindings(&sources)) {
        panic!("cannot write {}: {e}", target.display());
    }
}

/// One `@group(G) @binding(B) var<…> name: type;` line of a module.
struct Declaration {
    group: String,
    binding: u32,
    name: String,
    space: String,
    ty: String,
}

/// The declaration of one line, if it is one (written on one line, `@group` first; a `//`
/// comment is not read).
fn declaration(line: &str) -> Option<Declaration> {
    let line = line.split("//").next()?;
    let inner = |text: &str, open: &str| -> Option<(String, usize)> {
        let start = text.find(open)? + open.len();
        let end = start + text[start..].find(')')?;
        Some((text[start..end].trim().to_string(), end + 1))
    };
    let (group, after_group) = inner(line, "@group(")?;
    let (binding, after_binding) = inner(&line[after_group..], "@binding(")?;
    let rest = line[after_group + after_binding..]
        .trim_start()
        .strip_prefix("var")?;
    let (space, rest) = match rest.strip_prefix('<') {
        Some(r) => {
            let end = r.find('>')?;
            (r[..end].trim().to_string(), &r[end + 1..])
        }
        None => (String::new(), rest),
    };
    let (name, ty) = rest.split_once(':')?;
    Some(Declaration {
        group,
        binding: binding.parse().ok()?,
        name: name.trim().to_string(),
        space,
        ty: ty.trim().trim_end_matches(';').trim().to_string(),
    })
}

/// The module `stem` and every module it imports, each once.
fn with_imports<'a>(stem: &str, sources: &'a [(String, String)], out: &mut Vec<&'a str>) {
    let Some((name, text)) = sources.iter().find(|(s, _)| s == stem) else {
        return;
    };
    if out.contains(&name.as_str()) {
        return;
    }
    out.push(name.as_str());
    for line in text.lines() {
        if let Some(import) = line.trim().strip_prefix("#import ") {
            with_imports(import.trim(), sources, out);
        }
    }
}

/// Whether `text` passes `name` to a sampling or gathering function as its texture: the
/// first argument, or the second after a gather's component. A texture sampled only
/// through a function's parameter is not seen here; `tests/bindings.rs`, which reads
/// naga's validation of each composed shader, fails on it.
fn sampled(text: &str, name: &str) -> bool {
    ["textureSample", "textureGather"].iter().any(|function| {
        text.match_indices(function).any(|(at, _)| {
            let call = &text[at + function.len()..];
            let Some(open) = call.find('(') else {
                return false;
            };
            if !call[..open].chars().all(|c| c.is_ascii_alphanumeric()) {
                return false;
            }
            let mut arguments = call[open + 1..].split(',').map(str::trim);
            let first = arguments.next();
            first == Some(name) || (*function == "textureGather" && arguments.next() == Some(name))
        })
    })
}

/// The Rust `Binding` of one declaration, or `None` for a kind `BindGroupSpec` does not
/// bind (its group is then not generated).
fn binding_kind(d: &Declaration, text: &str) -> Option<String> {
    let float_texture = |dimension: &str| {
        if sampled(text, &d.name) {
            Some(format!(
                "Binding::Sampled(wgpu::TextureViewDimension::{dimension})"
            ))
        } else if dimension == "D2" {
            Some("Binding::TextureLoad".to_string())
        } else {
            None
        }
    };
    match (d.space.replace(' ', "").as_str(), d.ty.as_str()) {
        ("uniform", _) => Some("Binding::Uniform".into()),
        ("storage,read", _) => Some("Binding::Storage".into()),
        ("storage,read_write", _) => Some("Binding::StorageReadWrite".into()),
        ("", "texture_2d<f32>") => float_texture("D2"),
        ("", "texture_cube<f32>") => float_texture("Cube"),
        ("", "texture_depth_2d") => Some("Binding::Depth".into()),
        ("", "sampler") => Some("Binding::Sampler".into()),
        ("", "sampler_comparison") => Some("Binding::ComparisonSampler".into()),
        ("", "texture_storage_2d<rgba16float, write>") => {
            Some("Binding::StorageTexture(wgpu::TextureFormat::Rgba16Float)".into())
        }
        _ => None,
    }
}

/// `pub const STEM_GROUP: &[(&str, Binding)]` for every group of every module with an
/// entry point, its imports' declarations included, where the group's bindings run from 0
/// without a gap and every one is of a kind `BindGroupSpec` binds.
fn declared_bindings(sources: &[(String, String)]) -> String {
    let mut out = String::new();
    for (stem, text) in sources {
        if !["@fragment", "@compute", "@vertex"]
            .iter()
            .any(|s| text.contains(s))
        {
            continue;
        }
        let mut modules = Vec::new();
        with_imports(stem, sources, &mut modules);
        let texts: Vec<&str> = modules
            .iter()
            .filter_map(|m| {
                sources
                    .iter()
                    .find(|(s, _)| s == m)
                    .map(|(_, t)| t.as_str())
            })
            .collect();
        let all = texts.join("\n");
        let mut declarations: Vec<Declaration> = all.lines().filter_map(declaration).collect();
        declarations.sort_by(|a, b| (&a.group, a.binding).cmp(&(&b.group, b.binding)));
        let mut groups: Vec<&str> = declarations.iter().map(|d| d.group.as_str()).collect();
        groups.dedup();
        for group in groups {
            let members: Vec<&Declaration> =
                declarations.iter().filter(|d| d.group == group).collect();
            let contiguous = members.iter().zip(0u32..).all(|(d, i)| d.binding == i);
            let kinds: Option<Vec<String>> =
                members.iter().map(|d| binding_kind(d, &all)).collect();
            let (true, Some(kinds)) = (contiguous, kinds) else {
                continue;
            };
            let _ = writeln!(
                out,
                "/// Group `{group}` as `{stem}.wgsl` and its imports declare it.\n\
                 pub const {}_{}: &[(&str, Binding)] = &[",
                stem.to_uppercase(),
                group.to_uppercase()
            );
            for (d, kind) in members.iter().zip(kinds) {
                let _ = writeln!(out, "    ({:?}, {kind}),", d.name);
            }
            out.push_str("];\n");
        }
    }
    out
}
