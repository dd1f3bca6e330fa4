//! WGSL sources and their composition.
//!
//! WGSL has no `#include`, so Lumen adds one line of its own: a module names what it
//! uses with `#import NAME` lines (`NAME` is a file of `shaders/` without `.wgsl`), and
//! [`ShaderLibrary::compose`] resolves them: every module once, each after the modules it
//! imports, preceded by a header of constants (the "shader defs") that select the features
//! the scene needs. A feature a scene doesn't use is a `false` constant, so its code is
//! removed when the pipeline is compiled. A missing or circular import is an error that
//! names the file and its line.
//!
//! Every `.wgsl` file of `shaders/` is compiled into the binary ([`BUILTIN`], listed by
//! the build script), so `lumen` runs from any directory and a new shader needs no
//! registration. A [`ShaderLibrary`] can override them with files read from disk at run
//! time ([`crate::App::reload_shaders`], the viewer's hot reload). A compile error names
//! the module and the line in that module, not in the composed source ([`Composed`],
//! [`crate::render::pipelines::create_module`]).

use crate::error::{Error, Result};
use std::collections::HashMap;
use std::path::Path;
use std::sync::{Arc, RwLock};
use wgpu::naga;

/// Every WGSL module of `shaders/`, as (file name, source compiled into the binary).
pub const BUILTIN: &[(&str, &str)] = include!(concat!(env!("OUT_DIR"), "/builtin_shaders.rs"));

/// The built-in source of `file` (e.g. `tonemap.wgsl`).
pub fn builtin(file: &str) -> Option<&'static str> {
    BUILTIN.iter().find(|(f, _)| *f == file).map(|(_, s)| *s)
}

/// The WGSL sources passes compile from: the built-in ones, with overrides read from disk.
/// Cloning shares the overrides (every clone of a [`crate::render::device::Gpu`] sees a
/// reload).
#[derive(Clone, Debug, Default)]
pub struct ShaderLibrary {
    overrides: Arc<RwLock<HashMap<&'static str, Arc<str>>>>,
}

/// Overridden sources by file name.
pub type ShaderOverrides = HashMap<&'static str, Arc<str>>;

impl ShaderLibrary {
    /// The current source of `file`, if it is a module of `shaders/`.
    pub fn source(&self, file: &str) -> Option<Arc<str>> {
        self.overrides()
            .get(file)
            .cloned()
            .or_else(|| builtin(file).map(Arc::from))
    }

    /// The module `entry` (e.g. `lighting.wgsl`) with everything it imports, under `defs`.
    pub fn compose(&self, entry: &str, defs: &[ShaderDef]) -> Result<Composed> {
        let source = self
            .source(entry)
            .ok_or_else(|| Error::Gpu(format!("shader {entry}: no such file in shaders/")))?;
        self.compose_source(entry, &source, defs)
    }

    /// [`ShaderLibrary::compose`] for an entry module given as text (named `name` in
    /// errors), whose imports come from the library.
    pub fn compose_source(&self, name: &str, source: &str, defs: &[ShaderDef]) -> Result<Composed> {
        let mut composed = Composed::header(defs);
        let mut stack = Vec::new();
        let mut done = Vec::new();
        self.append(name, source, defs, (&mut stack, &mut done), &mut composed)?;
        Ok(composed)
    }

    fn append(
        &self,
        name: &str,
        source: &str,
        defs: &[ShaderDef],
        (stack, done): (&mut Vec<String>, &mut Vec<String>),
        out: &mut Composed,
    ) -> Result<()> {
        stack.push(name.to_string());
        for (line, import) in imports(source) {
            let import = defs
                .iter()
                .find_map(|d| match d {
                    ShaderDef::Import(from, to) if *from == import => Some(*to),
                    _ => None,
                })
                .unwrap_or(import);
            let file = format!("{import}.wgsl");
            if stack.contains(&file) {
                let mut cycle = stack.clone();
                cycle.push(file);
                return Err(Error::Gpu(format!(
                    "shaders/{name}:{line}: circular import ({})",
                    cycle.join(" → ")
                )));
            }
            if done.contains(&file) {
                continue;
            }
            let text = self.source(&file).ok_or_else(|| {
                Error::Gpu(format!(
                    "shaders/{name}:{line}: imports '{import}', but shaders/{file} does not exist"
                ))
            })?;
            self.append(&file, &text, defs, (&mut *stack, &mut *done), out)?;
        }
        stack.pop();
        done.push(name.to_string());
        out.push_module(name, source);
        Ok(())
    }

    /// The overrides in force.
    pub fn overrides(&self) -> ShaderOverrides {
        match self.overrides.read() {
            Ok(map) => map.clone(),
            Err(poisoned) => poisoned.into_inner().clone(),
        }
    }

    /// Replaces the overrides.
    pub fn set_overrides(&self, overrides: ShaderOverrides) {
        match self.overrides.write() {
            Ok(mut map) => *map = overrides,
            Err(poisoned) => *poisoned.into_inner() = overrides,
        }
    }
}

/// The `#import NAME` lines of a module: (1-based line, NAME).
fn imports(source: &str) -> impl Iterator<Item = (usize, &str)> {
    source.lines().enumerate().filter_map(|(i, line)| {
        line.trim()
            .strip_prefix("#import ")
            .map(|name| (i + 1, name.trim()))
    })
}

/// Reads every module of [`BUILTIN`] that exists in `dir` and differs from the built-in
/// source. A file that is missing keeps the built-in source; one that cannot be read
/// is an error.
pub fn read_overrides(dir: &Path) -> Result<ShaderOverrides> {
    if !dir.is_dir() {
        return Err(Error::InvalidArgument(format!(
            "shader folder {} does not exist",
            dir.display()
        )));
    }
    let mut out = HashMap::new();
    for &(file, builtin) in BUILTIN {
        let path = dir.join(file);
        if !path.exists() {
            continue;
        }
        let text = crate::files::read_text(&path)?;
        if text != builtin {
            out.insert(file, Arc::from(text));
        }
    }
    Ok(out)
}

/// One compile-time constant of a shader variant.
#[derive(Clone, Debug, PartialEq)]
pub enum ShaderDef {
    /// `const NAME: bool = value;`
    Bool(&'static str, bool),
    /// `const NAME: u32 = value;`
    U32(&'static str, u32),
    /// `var<private> NAME: bool = value;`: a switch the shader may turn per call where a
    /// [`ShaderDef::Bool`] of that name is read (the transparent pass's layered surfaces
    /// light their base, their sheen and their coat, each with its own lobe, in one
    /// fragment: `shaders/blended_layers.wgsl`).
    Switch(&'static str, bool),
    /// `#import FROM` reads the module `TO` instead (an alternative implementation of the
    /// same functions, e.g. without bindings the layout lacks).
    Import(&'static str, &'static str),
}

/// A composed WGSL source and where each of its lines came from.
#[derive(Clone, Debug, PartialEq)]
pub struct Composed {
    /// The WGSL text the compiler gets.
    pub source: String,
    /// Lines in `source` so far.
    lines: usize,
    /// (first line in `source`, module, its line count), 1-based, in order.
    segments: Vec<(usize, String, usize)>,
}

impl Composed {
    fn header(defs: &[ShaderDef]) -> Composed {
        let mut source = String::from("// Composed by lumen::render::shaders.\n");
        for def in defs {
            match def {
                ShaderDef::Bool(name, v) => {
                    source.push_str(&format!("const {name}: bool = {v};\n"))
                }
                ShaderDef::U32(name, v) => source.push_str(&format!("const {name}: u32 = {v}u;\n")),
                ShaderDef::Switch(name, v) => {
                    source.push_str(&format!("var<private> {name}: bool = {v};\n"))
                }
                ShaderDef::Import(..) => {}
            }
        }
        Composed {
            lines: source.lines().count(),
            source,
            segments: Vec::new(),
        }
    }

    /// Appends a module, its `#import` lines blanked (so its lines keep their numbers).
    fn push_module(&mut self, name: &str, text: &str) {
        self.source.push('\n');
        self.lines += 1;
        let first = self.lines + 1;
        let mut lines = 0;
        for line in text.lines() {
            if !line.trim().starts_with("#import ") {
                self.source.push_str(line);
            }
            self.source.push('\n');
            lines += 1;
        }
        self.lines += lines;
        self.segments.push((first, name.to_string(), lines));
    }

    /// The module and the line in it (1-based) of line `line` of [`Composed::source`].
    pub fn locate(&self, line: usize) -> Option<(&str, usize)> {
        self.segments
            .iter()
            .find(|(first, _, n)| line >= *first && line < first + n)
            .map(|(first, name, _)| (name.as_str(), line - first + 1))
    }

    /// Where naga puts the first error of this source, as `shaders/FILE:LINE:COLUMN:
    /// message`, if it finds one (parse or validation).
    pub fn first_error(&self) -> Option<String> {
        let (message, location) = match naga::front::wgsl::parse_str(&self.source) {
            Err(e) => (e.message().to_string(), e.location(&self.source)),
            Ok(module) => {
                let mut validator = naga::valid::Validator::new(
                    naga::valid::ValidationFlags::all(),
                    naga::valid::Capabilities::all(),
                );
                let e = validator.validate(&module).err()?;
                let location = e
                    .spans()
                    .next()
                    .map(|(span, _)| span.location(&self.source));
                (e.as_inner().to_string(), location)
            }
        };
        let location = location?;
        let (file, line) = self.locate(location.line_number as usize)?;
        Some(format!(
            "shaders/{file}:{line}:{}: {message}",
            location.line_position
        ))
    }
}

/// A WGSL struct as naga lays it out: its size and each member's name and offset, in
/// bytes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StructLayout {
    /// Its size, padding included.
    pub size: u32,
    /// (name, offset) of each member, in order.
    pub members: Vec<(String, u32)>,
}

/// The layout of struct `name` in the built-in module `entry` composed with `defs`, as
/// naga's layouter computes it (WGSL's alignment and size rules): what a `#[repr(C)]`
/// Rust twin must match ([`assert_wgsl_twin`](crate::assert_wgsl_twin)).
pub fn struct_layout(entry: &str, defs: &[ShaderDef], name: &str) -> Result<StructLayout> {
    let composed = ShaderLibrary::default().compose(entry, defs)?;
    let module = naga::front::wgsl::parse_str(&composed.source)
        .map_err(|e| Error::Gpu(format!("{entry}: {}", e.emit_to_string(&composed.source))))?;
    let mut layouter = naga::proc::Layouter::default();
    layouter
        .update(module.to_ctx())
        .map_err(|e| Error::Gpu(format!("{entry}: laying out its types: {e}")))?;
    module
        .types
        .iter()
        .find_map(|(_, ty)| match &ty.inner {
            naga::TypeInner::Struct { members, span } if ty.name.as_deref() == Some(name) => {
                Some(StructLayout {
                    size: *span,
                    members: members
                        .iter()
                        .map(|m| (m.name.clone().unwrap_or_default(), m.offset))
                        .collect(),
                })
            }
            _ => None,
        })
        .ok_or_else(|| Error::Gpu(format!("{entry} declares no struct {name}")))
}

/// Asserts that the `#[repr(C)]` Rust type `$ty` lays out as WGSL struct `$wgsl` of the
/// module `$entry` (composed with the defs `$defs`) does, by naga's layouter: the same
/// size, and each listed field at the offset of the member of the same name (or of the
/// member named after `=>`, for a Rust array that WGSL writes as numbered members).
/// Every WGSL member must fall inside a listed field, so a member added to one side
/// only fails it.
#[macro_export]
macro_rules! assert_wgsl_twin {
    ($ty:ty, $entry:expr, $defs:expr, $wgsl:expr, [$($field:ident $(=> $member:expr)?),+ $(,)?]) => {{
        let layout = $crate::render::shaders::struct_layout($entry, $defs, $wgsl)
            .unwrap_or_else(|e| panic!("{e}"));
        let twin = stringify!($ty);
        assert_eq!(
            std::mem::size_of::<$ty>() as u32,
            layout.size,
            "{twin}: size of the Rust twin of {}",
            $wgsl
        );
        let fields: Vec<(&str, u32)> = vec![$(
            (
                $crate::assert_wgsl_twin!(@member $field $(=> $member)?),
                std::mem::offset_of!($ty, $field) as u32,
            )
        ),+];
        for (member, offset) in &fields {
            let found = layout.members.iter().find(|(m, _)| m == member);
            assert_eq!(
                found.map(|(_, o)| *o),
                Some(*offset),
                "{twin}: member {member} of {} (WGSL layout {:?})",
                $wgsl,
                layout.members
            );
        }
        // A member no field names lies inside a listed field (the later elements of an
        // array WGSL writes as numbered members).
        let mut starts: Vec<u32> = fields.iter().map(|(_, o)| *o).collect();
        starts.sort_unstable();
        for (member, offset) in &layout.members {
            if fields.iter().any(|(f, _)| f == member) {
                continue;
            }
            let inside = starts.iter().any(|s| s < offset);
            assert!(
                inside && !starts.contains(offset),
                "{twin}: member {member} of {} (offset {offset}) is in no listed field",
                $wgsl
            );
        }
    }};
    (@member $field:ident => $member:expr) => { $member };
    (@member $field:ident) => { stringify!($field) };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    #[should_panic(expected = "size of the Rust twin")]
    fn a_twin_missing_a_field_fails() {
        #[repr(C)]
        struct Short {
            clip_from_world: [[f32; 4]; 4],
        }
        crate::assert_wgsl_twin!(Short, "bindings.wgsl", &[], "ShadowView", [clip_from_world]);
    }

    #[test]
    #[should_panic(expected = "member texel")]
    fn a_twin_with_fields_swapped_fails() {
        #[repr(C)]
        struct Swapped {
            clip_from_world: [[f32; 4]; 4],
            texel: [f32; 4],
            rect: [f32; 4],
        }
        crate::assert_wgsl_twin!(
            Swapped,
            "bindings.wgsl",
            &[],
            "ShadowView",
            [clip_from_world, texel, rect]
        );
    }

    fn library(files: &[(&'static str, &str)]) -> ShaderLibrary {
        let library = ShaderLibrary::default();
        library.set_overrides(files.iter().map(|(f, s)| (*f, Arc::from(*s))).collect());
        library
    }

    #[test]
    fn imports_come_first_once_and_errors_map_to_the_module_line() {
        let lib = library(&[
            (
                "tonemap.wgsl",
                "#import common\n#import color\nfn a() -> f32 { return b(); }\n",
            ),
            (
                "color.wgsl",
                "#import common\nfn b() -> f32 { return PI; }\n",
            ),
            ("common.wgsl", "const PI: f32 = 3.14159;\n"),
        ]);
        let composed = lib
            .compose("tonemap.wgsl", &[ShaderDef::Bool("X", true)])
            .expect("composes");
        let pi = composed.source.find("const PI").expect("common");
        let b = composed.source.find("fn b").expect("color");
        let a = composed.source.find("fn a").expect("tonemap");
        assert!(pi < b && b < a, "{}", composed.source);
        assert_eq!(composed.source.matches("const PI").count(), 1);
        assert!(!composed.source.contains("#import"));
        let line_of = |at: usize| composed.source[..at].lines().count() + 1;
        assert_eq!(composed.locate(line_of(a)), Some(("tonemap.wgsl", 3)));
        assert_eq!(composed.locate(line_of(b)), Some(("color.wgsl", 2)));
        assert_eq!(composed.first_error(), None);
    }

    #[test]
    fn a_type_error_names_the_module_and_its_own_line() {
        let lib = library(&[
            (
                "tonemap.wgsl",
                "#import color\n\n\nfn a() -> f32 { return b(); }\n",
            ),
            ("color.wgsl", "fn b() -> f32 {\n    return 1u;\n}\n"),
        ]);
        let composed = lib.compose("tonemap.wgsl", &[]).expect("composes");
        let error = composed.first_error().expect("a type error");
        assert!(error.starts_with("shaders/color.wgsl:"), "{error}");
        let lib = library(&[("tonemap.wgsl", "\n\nfn a( -> f32 {}\n")]);
        let error = lib
            .compose("tonemap.wgsl", &[])
            .expect("composes")
            .first_error()
            .expect("a syntax error");
        assert!(error.starts_with("shaders/tonemap.wgsl:3:"), "{error}");
    }

    #[test]
    fn missing_and_circular_imports_are_errors_naming_the_file() {
        let lib = library(&[("tonemap.wgsl", "\n#import nowhere\n")]);
        let err = lib
            .compose("tonemap.wgsl", &[])
            .expect_err("missing")
            .to_string();
        assert!(
            err.contains("shaders/tonemap.wgsl:2") && err.contains("nowhere"),
            "{err}"
        );
        let lib = library(&[
            ("tonemap.wgsl", "#import color\n"),
            ("color.wgsl", "#import tonemap\n"),
        ]);
        let err = lib
            .compose("tonemap.wgsl", &[])
            .expect_err("cycle")
            .to_string();
        assert!(err.contains("circular import"), "{err}");
        assert!(err.contains("shaders/color.wgsl:1"), "{err}");
        let err = lib
            .compose("nothing.wgsl", &[])
            .expect_err("no entry")
            .to_string();
        assert!(err.contains("nothing.wgsl"), "{err}");
    }

    #[test]
    fn every_builtin_module_composes() {
        let lib = ShaderLibrary::default();
        for (file, _) in BUILTIN {
            lib.compose(file, &[]).expect("imports resolve");
        }
    }
}
