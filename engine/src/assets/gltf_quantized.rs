//! `KHR_mesh_quantization`: vertex attributes (positions, normals, tangents, texture
//! coordinates, morph target offsets) stored as 8- or 16-bit integers, normalized or not,
//! read here as f32.
//!
//! The conversion is the glTF 2.0 specification's for normalized integers (its section
//! 3.11, Animations), which the extension's README applies to vertex attributes (Khronos
//! 2019, "KHR_mesh_quantization"): a normalized integer `c`
//! of a signed type of `b` bits is `max(c / (2^(b−1) − 1), −1)`, of an unsigned type
//! `c / (2^b − 1)`; an unnormalized one is `c` itself. A file undoes the quantization of
//! its positions with its nodes' transforms, which the loader applies as usual. Quantized
//! normals and tangents are not unit length: they are normalized after reading, as the
//! extension says applications do.

use super::gltf_buffers::view_bytes;
use gltf::accessor::DataType;

/// The extension's name.
pub const EXTENSION: &str = "KHR_mesh_quantization";

/// One component of type `kind` from its little-endian `bytes`, as f32, by the
/// specification's conversion.
pub fn dequantize(kind: DataType, normalized: bool, bytes: &[u8]) -> f32 {
    let at = |n: usize| bytes.get(n).copied().unwrap_or(0);
    let two = [at(0), at(1)];
    match (kind, normalized) {
        (DataType::I8, true) => (f32::from(at(0) as i8) / 127.0).max(-1.0),
        (DataType::I8, false) => f32::from(at(0) as i8),
        (DataType::U8, true) => f32::from(at(0)) / 255.0,
        (DataType::U8, false) => f32::from(at(0)),
        (DataType::I16, true) => (f32::from(i16::from_le_bytes(two)) / 32767.0).max(-1.0),
        (DataType::I16, false) => f32::from(i16::from_le_bytes(two)),
        (DataType::U16, true) => f32::from(u16::from_le_bytes(two)) / 65535.0,
        (DataType::U16, false) => f32::from(u16::from_le_bytes(two)),
        (DataType::U32, _) => u32::from_le_bytes([at(0), at(1), at(2), at(3)]) as f32,
        (DataType::F32, _) => f32::from_le_bytes([at(0), at(1), at(2), at(3)]),
    }
}

/// The elements of `accessor`, `N` components each, as f32: through `floats` (the glTF
/// crate's reader, which also reads sparse accessors) when they are f32, and dequantized
/// here otherwise. A quantized accessor that is sparse, or whose elements are not `N`
/// wide, is an error naming it. The accessor's bounds were checked before
/// (`check_accessor`).
pub(super) fn read_attribute<const N: usize>(
    accessor: &gltf::Accessor,
    buffers: &[gltf::buffer::Data],
    floats: impl FnOnce() -> Option<Vec<[f32; N]>>,
) -> Result<Option<Vec<[f32; N]>>, String> {
    let kind = accessor.data_type();
    if kind == DataType::F32 {
        return Ok(floats());
    }
    let name = format!("accessor {} ({kind:?})", accessor.index());
    if accessor.dimensions().multiplicity() != N {
        return Err(format!(
            "{name}: {:?} elements where {N} components are read",
            accessor.dimensions()
        ));
    }
    if accessor.sparse().is_some() {
        return Err(format!(
            "{name}: sparse quantized attributes are not read ({EXTENSION})"
        ));
    }
    let Some(view) = accessor.view() else {
        return Ok(Some(vec![[0.0; N]; accessor.count()]));
    };
    let bytes = view_bytes(&view, buffers).ok_or(format!("{name}: outside its buffer"))?;
    let size = kind.size();
    let stride = view
        .stride()
        .unwrap_or(accessor.size())
        .max(accessor.size());
    let normalized = accessor.normalized();
    (0..accessor.count())
        .map(|i| {
            let start = accessor.offset() + i * stride;
            let element = bytes
                .get(start..start + N * size)
                .ok_or(format!("{name}: element {i} lies outside its buffer view"))?;
            Ok(std::array::from_fn(|c| {
                dequantize(kind, normalized, &element[c * size..])
            }))
        })
        .collect::<Result<Vec<_>, String>>()
        .map(Some)
}

/// `v` scaled to unit length (a quantized direction is not quite); a zero vector stays.
pub fn unit3(v: [f32; 3]) -> [f32; 3] {
    let length = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if length > 0.0 {
        v.map(|x| x / length)
    } else {
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integers_dequantize_as_the_specification_says() {
        assert_eq!(dequantize(DataType::I8, true, &[127]), 1.0);
        assert_eq!(dequantize(DataType::I8, true, &[0x81]), -1.0);
        // −128 clamps to −1 rather than −1.008.
        assert_eq!(dequantize(DataType::I8, true, &[0x80]), -1.0);
        assert_eq!(dequantize(DataType::U8, true, &[255]), 1.0);
        assert_eq!(dequantize(DataType::U8, false, &[200]), 200.0);
        let i16n = dequantize(DataType::I16, true, &(-16384i16).to_le_bytes());
        assert!((i16n + 16384.0 / 32767.0).abs() < 1e-7, "{i16n}");
        assert_eq!(
            dequantize(DataType::I16, true, &i16::MIN.to_le_bytes()),
            -1.0
        );
        assert_eq!(
            dequantize(DataType::U16, true, &u16::MAX.to_le_bytes()),
            1.0
        );
        assert_eq!(dequantize(DataType::U16, false, &[0x34, 0x12]), 4660.0);
        assert_eq!(
            dequantize(DataType::I16, false, &(-3i16).to_le_bytes()),
            -3.0
        );
        assert_eq!(dequantize(DataType::F32, false, &1.5f32.to_le_bytes()), 1.5);
    }

    #[test]
    fn directions_are_made_unit_and_zero_stays_zero() {
        let n = unit3([0.0, 127.0 / 127.0, 1.0]);
        assert!((n[1] - std::f32::consts::FRAC_1_SQRT_2).abs() < 1e-6);
        assert_eq!(unit3([0.0; 3]), [0.0; 3]);
    }
}
