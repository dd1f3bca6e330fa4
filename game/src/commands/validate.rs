//! `lumen validate`: the PBR texture validator on glTF materials or texture files.

use crate::cli::ValidateArgs;
use crate::materials::{NamedMaterial, file_stem, gltf_materials};
use anyhow::{Context, Result, anyhow};
use lumen::validate::{MaterialInput, Report, validate_with_progress};
use std::path::Path;

/// Some texel of some material fails a rule (`lumen` exits with status 3).
#[derive(Debug)]
pub struct ValidationFailed {
    /// Failing materials.
    pub failing: usize,
    /// Materials checked.
    pub materials: usize,
}

impl std::fmt::Display for ValidationFailed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} of {} material(s) fail the PBR rules",
            self.failing, self.materials
        )
    }
}

impl std::error::Error for ValidationFailed {}

/// Runs the validator and prints its report; an error [`ValidationFailed`] when any
/// texel fails a rule.
pub fn run(args: &ValidateArgs) -> Result<()> {
    if args.files.is_empty() && !args.textures.any() {
        return Err(anyhow!(
            "nothing to validate: give glTF files or texture files by role (see lumen validate --help)"
        ));
    }
    let mut materials: Vec<NamedMaterial> = Vec::new();
    for file in &args.files {
        materials.extend(gltf_materials(file)?);
    }
    if args.textures.any() {
        materials.push(args.textures.material()?);
    }
    let mut text = String::new();
    let mut json = Vec::new();
    let mut failing = 0;
    for (k, m) in materials.iter().enumerate() {
        let bar = crate::progress::bar(u64::from(m.input.size().1), "validating", "rows");
        let report = validate_with_progress(&m.input, args.strict, &|| bar.inc(1));
        bar.finish_and_clear();
        failing += usize::from(!report.passes());
        text.push_str(&summary(m, &report));
        if let Some(dir) = &args.heatmap {
            write_heatmaps(dir, k, m, &report)?;
        }
        json.push(material_json(m, &report));
    }
    let all_pass = failing == 0;
    text.push_str(&format!(
        "{}: {} material(s){}\n",
        if all_pass { "PASS" } else { "FAIL" },
        materials.len(),
        if args.strict { ", strict" } else { "" }
    ));
    let doc = serde_json::json!({
        "schema": "lumen-validate/1",
        "strict": args.strict,
        "passes": all_pass,
        "materials": json,
    });
    match args.json.as_deref() {
        Some(p) if p == Path::new("-") => {
            crate::output::print(&format!("{doc:#}\n"));
            eprint!("{text}");
        }
        Some(p) => {
            crate::output::write_text(p, &format!("{doc:#}\n"))?;
            crate::output::print(&text);
        }
        None => crate::output::print(&text),
    }
    if all_pass {
        Ok(())
    } else {
        Err(ValidationFailed {
            failing,
            materials: materials.len(),
        }
        .into())
    }
}

fn workflow_name(input: &MaterialInput) -> &'static str {
    match input {
        MaterialInput::MetalRough { .. } => "metal/roughness",
        MaterialInput::SpecGloss { .. } => "specular/glossiness",
    }
}

fn summary(m: &NamedMaterial, report: &Report) -> String {
    let mut out = format!(
        "{} · {} ({}, {}x{}): {}\n",
        m.source.display(),
        m.name,
        workflow_name(&m.input),
        report.size.0,
        report.size.1,
        if report.passes() { "pass" } else { "FAIL" }
    );
    for r in &report.rules {
        let share = |n: u64| {
            if r.checked == 0 {
                0.0
            } else {
                100.0 * n as f64 / r.checked as f64
            }
        };
        out.push_str(&format!(
            "  {:<18} {:>7.2} % invalid, {:>7.2} % borderline of {} texel(s){}\n",
            r.rule.name(),
            share(r.invalid),
            share(r.borderline),
            r.checked,
            if r.checked == 0 {
                " (not applicable)"
            } else {
                ""
            }
        ));
    }
    out
}

fn material_json(m: &NamedMaterial, report: &Report) -> serde_json::Value {
    serde_json::json!({
        "source": m.source.display().to_string(),
        "name": m.name,
        "workflow": workflow_name(&m.input),
        "width": report.size.0,
        "height": report.size.1,
        "passes": report.passes(),
        "rules": report.rules.iter().map(|r| serde_json::json!({
            "rule": r.rule.name(),
            "checked": r.checked,
            "invalid": r.invalid,
            "borderline": r.borderline,
            "invalid_share": r.invalid_share(),
        })).collect::<Vec<_>>(),
    })
}

/// `DIR/<k>-<material>.png` (worst verdict) and `DIR/<k>-<material>-<rule>.png`.
fn write_heatmaps(dir: &Path, k: usize, m: &NamedMaterial, report: &Report) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let stem = format!("{k}-{}", file_stem(&m.name));
    let save = |name: String, image: &image::RgbImage| -> Result<()> {
        let path = dir.join(name);
        lumen::assets::image_io::save(&path, image, image::ImageFormat::Png)
            .with_context(|| format!("writing {}", path.display()))
    };
    save(format!("{stem}.png"), &report.heatmap)?;
    for r in &report.rules {
        save(format!("{stem}-{}.png", r.rule.name()), &r.heatmap)?;
    }
    Ok(())
}
