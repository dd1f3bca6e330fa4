//! `lumen bench --compare A.json B.json`: the ratio B / A of the medians of the frame, the
//! GPU total, every pass's GPU time and every CPU stage.

use super::report::SCHEMA;
use anyhow::{Context, Result, anyhow};
use serde_json::Value;
use std::fmt::Write as _;
use std::path::Path;

/// One compared quantity: its name and the medians (ms) in A and B.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// `frame`, `gpu`, `<pass> (gpu)` or `cpu <stage>`.
    pub name: String,
    /// Median in A (ms), if A has it.
    pub a: Option<f64>,
    /// Median in B (ms), if B has it.
    pub b: Option<f64>,
}

impl Row {
    /// B / A; `None` unless both exist and A > 0.
    pub fn ratio(&self) -> Option<f64> {
        match (self.a, self.b) {
            (Some(a), Some(b)) if a > 0.0 => Some(b / a),
            _ => None,
        }
    }
}

fn load(path: &Path) -> Result<Value> {
    let text = lumen::files::read_text(path)?;
    let v: Value =
        serde_json::from_str(&text).with_context(|| format!("{} is not JSON", path.display()))?;
    if v["schema"] != SCHEMA {
        return Err(anyhow!(
            "{} is not a lumen bench report (schema {SCHEMA})",
            path.display()
        ));
    }
    Ok(v)
}

fn median(v: &Value) -> Option<f64> {
    v["median"].as_f64()
}

fn named(
    v: &Value,
    list: &str,
    field: &str,
    prefix: &str,
    suffix: &str,
) -> Vec<(String, Option<f64>)> {
    v[list]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|e| {
            let name = e["name"].as_str()?;
            Some((format!("{prefix}{name}{suffix}"), median(&e[field])))
        })
        .collect()
}

fn rows_of(v: &Value) -> Vec<(String, Option<f64>)> {
    let mut rows = vec![
        ("frame".to_string(), median(&v["frame_ms"])),
        ("gpu".to_string(), median(&v["gpu_ms"])),
    ];
    rows.extend(named(v, "passes", "gpu_ms", "", " (gpu)"));
    rows.extend(named(v, "cpu_stages", "ms", "cpu ", ""));
    rows
}

/// The rows of A and B, in A's order, then what only B has.
pub fn compare(a_path: &Path, b_path: &Path) -> Result<Vec<Row>> {
    let (a, b) = (rows_of(&load(a_path)?), rows_of(&load(b_path)?));
    let mut rows: Vec<Row> = a
        .iter()
        .map(|(name, va)| Row {
            name: name.clone(),
            a: *va,
            b: b.iter().find(|(n, _)| n == name).and_then(|(_, v)| *v),
        })
        .collect();
    for (name, vb) in &b {
        if !rows.iter().any(|r| &r.name == name) {
            rows.push(Row {
                name: name.clone(),
                a: None,
                b: *vb,
            });
        }
    }
    Ok(rows)
}

/// The comparison as a table.
pub fn to_text(a_path: &Path, b_path: &Path, rows: &[Row]) -> String {
    let mut out = format!(
        "medians, B / A  (A = {}, B = {})\n  {:<24} {:>11} {:>11} {:>8}\n",
        a_path.display(),
        b_path.display(),
        "",
        "A",
        "B",
        "B / A"
    );
    let ms = |v: Option<f64>| v.map_or("—".to_string(), |v| format!("{v:.3} ms"));
    for r in rows {
        let ratio = r.ratio().map_or("—".to_string(), |x| format!("{x:.3}"));
        let _ = writeln!(
            out,
            "  {:<24} {:>11} {:>11} {:>8}",
            r.name,
            ms(r.a),
            ms(r.b),
            ratio
        );
    }
    out
}
