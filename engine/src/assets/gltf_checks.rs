//! Checks a glTF document before the `gltf` crate's own code indexes with its values.
//!
//! - The crate reads every index as a `u32` by truncation (`4294967296` becomes 0), so an
//!   out-of-range index would silently name the first element. [`check_index_ranges`] reads
//!   the raw JSON and refuses any index that does not fit in a `u32`.
//! - The crate's validation reads `accessors[POSITION]` without a bounds check, and panics
//!   on an attribute that names a missing accessor. [`check_attribute_accessors`] checks
//!   every primitive's attributes and morph targets first.

use serde_json::Value;

/// Object keys whose numbers are indices into one of the document's arrays (glTF 2.0 and
/// `KHR_lights_punctual`).
const INDEX_KEYS: &[&str] = &[
    "scene",
    "nodes",
    "children",
    "mesh",
    "camera",
    "skin",
    "skeleton",
    "joints",
    "inverseBindMatrices",
    "material",
    "indices",
    "attributes",
    "targets",
    "bufferView",
    "buffer",
    "sampler",
    "source",
    "index",
    "node",
    "input",
    "output",
    "light",
];

/// The JSON text of a `.gltf` or `.glb` file's bytes, or `None` if it is neither.
fn json_of(bytes: &[u8]) -> Option<std::borrow::Cow<'_, [u8]>> {
    if bytes.starts_with(b"glTF") {
        gltf::binary::Glb::from_slice(bytes)
            .ok()
            .map(|glb| glb.json)
    } else {
        Some(std::borrow::Cow::Borrowed(bytes))
    }
}

/// Refuses an index that does not fit in a `u32`, naming where it is. A document that is
/// not JSON passes: the parser reports it.
pub(super) fn check_index_ranges(bytes: &[u8]) -> Result<(), String> {
    let Some(value) = json_of(bytes).and_then(|json| serde_json::from_slice::<Value>(&json).ok())
    else {
        return Ok(());
    };
    let mut path = String::new();
    walk(&value, false, &mut path)
}

fn walk(value: &Value, indices: bool, path: &mut String) -> Result<(), String> {
    match value {
        Value::Number(n) if indices => match n.as_u64() {
            Some(i) if i > u64::from(u32::MAX) => Err(format!(
                "{path}: index {i} is out of range (at most {})",
                u32::MAX
            )),
            _ => Ok(()),
        },
        Value::Array(items) => {
            for (k, item) in items.iter().enumerate() {
                let len = path.len();
                path.push_str(&format!("[{k}]"));
                walk(item, indices, path)?;
                path.truncate(len);
            }
            Ok(())
        }
        Value::Object(fields) => {
            for (key, item) in fields {
                let len = path.len();
                if !path.is_empty() {
                    path.push('.');
                }
                path.push_str(key);
                // Inside `attributes` and `targets` every value is an index, whatever its
                // key (`POSITION`, `TEXCOORD_0`, …).
                walk(item, indices || INDEX_KEYS.contains(&key.as_ref()), path)?;
                path.truncate(len);
            }
            Ok(())
        }
        _ => Ok(()),
    }
}

/// Checks that every primitive attribute and morph target names an existing accessor.
pub(super) fn check_attribute_accessors(root: &gltf::json::Root) -> Result<(), String> {
    let count = root.accessors.len();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let at = format!("meshes[{m}].primitives[{p}]");
            for (semantic, index) in &primitive.attributes {
                let name = match semantic {
                    gltf::json::validation::Checked::Valid(s) => s.to_string(),
                    gltf::json::validation::Checked::Invalid => "an unknown attribute".into(),
                };
                missing(index.value(), count, || format!("{at}.attributes.{name}"))?;
            }
            for (t, target) in primitive.targets.iter().flatten().enumerate() {
                for (name, index) in [
                    ("POSITION", target.positions),
                    ("NORMAL", target.normals),
                    ("TANGENT", target.tangents),
                ] {
                    if let Some(index) = index {
                        missing(index.value(), count, || format!("{at}.targets[{t}].{name}"))?;
                    }
                }
            }
        }
    }
    Ok(())
}

fn missing(index: usize, count: usize, at: impl Fn() -> String) -> Result<(), String> {
    if index < count {
        Ok(())
    } else {
        Err(format!(
            "{}: accessor {index} does not exist (the file has {count})",
            at()
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn indices_past_u32_are_refused_with_their_path() {
        let doc =
            br#"{"meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":4294967296}]}]}"#;
        let e = check_index_ranges(doc).expect_err("out of range");
        assert!(
            e.contains("meshes[0].primitives[0].material: index 4294967296"),
            "{e}"
        );
        let doc = br#"{"meshes":[{"primitives":[{"attributes":{"TEXCOORD_0":4294967296}}]}]}"#;
        assert!(check_index_ranges(doc).is_err());
        // Large numbers that are not indices, and the largest u32 index, pass.
        let doc = br#"{"buffers":[{"byteLength":4294967296}],"scene":4294967295}"#;
        assert_eq!(check_index_ranges(doc), Ok(()));
        assert_eq!(check_index_ranges(b"not json"), Ok(()));
    }
}
