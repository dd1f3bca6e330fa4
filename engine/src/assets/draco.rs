//! Primitives compressed with `KHR_draco_mesh_compression`, decoded with the pure-Rust
//! `draco-core` decoder. The extension names a buffer view holding the Draco bitstream and
//! maps each glTF attribute (`POSITION`, `NORMAL`, `TEXCOORD_0`, …) to a Draco attribute's
//! unique id; the accessors of the primitive keep only their count and type.

use draco_core::decoder_buffer::DecoderBuffer;
use draco_core::draco_types::DataType;
use draco_core::geometry_attribute::PointAttribute;
use draco_core::geometry_indices::{FaceIndex, PointIndex};
use draco_core::mesh::Mesh;
use draco_core::mesh_decoder::MeshDecoder;

/// The extension's name.
pub const EXTENSION: &str = "KHR_draco_mesh_compression";

/// A decoded primitive: one entry per Draco point.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DracoPrimitive {
    /// Positions (m).
    pub positions: Vec<[f32; 3]>,
    /// Normals, where the file has them.
    pub normals: Option<Vec<[f32; 3]>>,
    /// Texture coordinates of set 0, where the file has them.
    pub uvs: Option<Vec<[f32; 2]>>,
    /// Triangle list.
    pub indices: Vec<u32>,
}

/// Decodes the Draco stream of a primitive whose extension object is `extension`
/// (`{"bufferView": i, "attributes": {...}}`), reading buffer views from `view_bytes`.
pub fn decode_primitive<'a>(
    extension: &gltf::json::Value,
    view_bytes: impl Fn(usize) -> Option<&'a [u8]>,
) -> Result<DracoPrimitive, String> {
    let view = extension
        .get("bufferView")
        .and_then(|v| v.as_u64())
        .ok_or(format!("{EXTENSION} without a bufferView"))?;
    let bytes = view_bytes(view as usize).ok_or(format!(
        "{EXTENSION}: buffer view {view} is missing or out of range"
    ))?;
    let attributes = extension
        .get("attributes")
        .and_then(|a| a.as_object())
        .ok_or(format!("{EXTENSION} without attributes"))?;
    // A unique id past u32 is refused, never truncated onto another attribute.
    let unique_id = |name: &str| -> Result<Option<u32>, String> {
        match attributes.get(name).and_then(|v| v.as_u64()) {
            None => Ok(None),
            Some(v) => u32::try_from(v).map(Some).map_err(|_| {
                format!("{EXTENSION}: Draco attribute id {v} for {name} is out of range")
            }),
        }
    };

    let mut buffer = DecoderBuffer::new(bytes);
    let mut mesh = Mesh::new();
    MeshDecoder::new()
        .decode(&mut buffer, &mut mesh)
        .map_err(|e| format!("Draco stream does not decode: {e}"))?;

    let points = mesh.num_points();
    let attribute = |name: &str| -> Result<Option<&PointAttribute>, String> {
        match unique_id(name)? {
            None => Ok(None),
            Some(id) => mesh
                .attribute_by_unique_id(id)
                .map(Some)
                .ok_or(format!("{EXTENSION}: no Draco attribute {id} for {name}")),
        }
    };
    let position = attribute("POSITION")?.ok_or(format!("{EXTENSION}: no POSITION"))?;
    let mut out = DracoPrimitive {
        positions: read_floats::<3>(position, points, "POSITION")?,
        ..DracoPrimitive::default()
    };
    if let Some(normal) = attribute("NORMAL")? {
        out.normals = Some(read_floats::<3>(normal, points, "NORMAL")?);
    }
    if let Some(uv) = attribute("TEXCOORD_0")? {
        out.uvs = Some(read_floats::<2>(uv, points, "TEXCOORD_0")?);
    }
    out.indices.reserve(mesh.num_faces() * 3);
    for f in 0..mesh.num_faces() {
        for PointIndex(p) in mesh.face(FaceIndex(f as u32)) {
            if p as usize >= points {
                return Err(format!("Draco face {f} points past the {points} points"));
            }
            out.indices.push(p);
        }
    }
    Ok(out)
}

/// The first `N` float components of every point of a decoded attribute.
fn read_floats<const N: usize>(
    attribute: &PointAttribute,
    points: usize,
    name: &str,
) -> Result<Vec<[f32; N]>, String> {
    if attribute.data_type() != DataType::Float32 || (attribute.num_components() as usize) < N {
        return Err(format!(
            "Draco {name} is {:?} × {}, not float × {N}",
            attribute.data_type(),
            attribute.num_components()
        ));
    }
    let stride = usize::try_from(attribute.byte_stride()).unwrap_or(0);
    let data = attribute.buffer().data();
    (0..points)
        .map(|p| {
            let value = attribute.mapped_index(PointIndex(p as u32)).0 as usize;
            let start = value.checked_mul(stride).ok_or("overflow")?;
            let bytes = data
                .get(start..start + 4 * N)
                .ok_or(format!("Draco {name} value {value} is out of range"))?;
            let mut v = [0f32; N];
            for (k, c) in v.iter_mut().enumerate() {
                let b = [
                    bytes[4 * k],
                    bytes[4 * k + 1],
                    bytes[4 * k + 2],
                    bytes[4 * k + 3],
                ];
                *c = f32::from_le_bytes(b);
            }
            Ok(v)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Draco stream and extension object of `assets/models/suzi.glb`.
    fn suzi() -> (Vec<u8>, gltf::json::Value) {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../assets/models/suzi.glb");
        let bytes = std::fs::read(path).expect("suzi.glb");
        let glb = gltf::Gltf::from_slice_without_validation(&bytes).expect("glb");
        let json = glb.document.as_json();
        let extension = json.meshes[0].primitives[0]
            .extensions
            .as_ref()
            .and_then(|e| e.others.get(EXTENSION))
            .cloned()
            .expect("draco extension");
        let view = &json.buffer_views[0];
        let start = view.byte_offset.map_or(0, |o| o.0 as usize);
        let end = start + view.byte_length.0 as usize;
        let blob = glb.blob.expect("binary chunk");
        (blob[start..end].to_vec(), extension)
    }

    #[test]
    fn attribute_ids_are_range_checked_not_truncated() {
        let (stream, mut extension) = suzi();
        let decoded = decode_primitive(&extension, |_| Some(&stream[..])).expect("decodes");
        assert_eq!(decoded.indices.len() / 3, 14_842);
        // 2³² would wrap to id 0, the positions, under an `as u32`.
        extension["attributes"]["NORMAL"] = gltf::json::Value::from(4_294_967_296u64);
        let e = decode_primitive(&extension, |_| Some(&stream[..])).expect_err("out of range");
        assert!(e.contains("4294967296 for NORMAL is out of range"), "{e}");
    }
}
